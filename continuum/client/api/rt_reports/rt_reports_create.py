from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.report_batch_request import ReportBatchRequest
from ...models.rt_reports_create_response_201 import RtReportsCreateResponse201
from ...types import Response


def _get_kwargs(
    *,
    body: ReportBatchRequest,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/rt-reports/",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> RtReportsCreateResponse201 | None:
    if response.status_code == 201:
        response_201 = RtReportsCreateResponse201.from_dict(response.json())

        return response_201

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[RtReportsCreateResponse201]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: ReportBatchRequest,
) -> Response[RtReportsCreateResponse201]:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        body (ReportBatchRequest): For the API docs only: the endpoint reads the body itself (it
            must be fast).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[RtReportsCreateResponse201]
    """

    kwargs = _get_kwargs(
        body=body,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    body: ReportBatchRequest,
) -> RtReportsCreateResponse201 | None:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        body (ReportBatchRequest): For the API docs only: the endpoint reads the body itself (it
            must be fast).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        RtReportsCreateResponse201
    """

    return sync_detailed(
        client=client,
        body=body,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: ReportBatchRequest,
) -> Response[RtReportsCreateResponse201]:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        body (ReportBatchRequest): For the API docs only: the endpoint reads the body itself (it
            must be fast).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[RtReportsCreateResponse201]
    """

    kwargs = _get_kwargs(
        body=body,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    body: ReportBatchRequest,
) -> RtReportsCreateResponse201 | None:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        body (ReportBatchRequest): For the API docs only: the endpoint reads the body itself (it
            must be fast).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        RtReportsCreateResponse201
    """

    return (
        await asyncio_detailed(
            client=client,
            body=body,
        )
    ).parsed
