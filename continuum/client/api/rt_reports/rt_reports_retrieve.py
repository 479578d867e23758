from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.monitoring_report import MonitoringReport
from ...types import Response


def _get_kwargs(
    id: int,
) -> dict[str, Any]:

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/rt-reports/{id}/".format(
            id=quote(str(id), safe=""),
        ),
    }

    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> MonitoringReport | None:
    if response.status_code == 200:
        response_200 = MonitoringReport.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[MonitoringReport]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
) -> Response[MonitoringReport]:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        id (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[MonitoringReport]
    """

    kwargs = _get_kwargs(
        id=id,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    id: int,
    *,
    client: AuthenticatedClient,
) -> MonitoringReport | None:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        id (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        MonitoringReport
    """

    return sync_detailed(
        id=id,
        client=client,
    ).parsed


async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
) -> Response[MonitoringReport]:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        id (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[MonitoringReport]
    """

    kwargs = _get_kwargs(
        id=id,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
) -> MonitoringReport | None:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        id (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        MonitoringReport
    """

    return (
        await asyncio_detailed(
            id=id,
            client=client,
        )
    ).parsed
