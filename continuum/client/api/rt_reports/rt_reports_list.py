from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_monitoring_report_list import PaginatedMonitoringReportList
from ...models.rt_reports_list_source import RtReportsListSource
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    cluster: int | Unset = UNSET,
    container_name: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    node: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    source: RtReportsListSource | Unset = UNSET,
    violation: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["cluster"] = cluster

    params["container_name"] = container_name

    params["limit"] = limit

    params["node"] = node

    params["offset"] = offset

    params["ordering"] = ordering

    params["search"] = search

    json_source: str | Unset = UNSET
    if not isinstance(source, Unset):
        json_source = source

    params["source"] = json_source

    params["violation"] = violation

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/rt-reports/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedMonitoringReportList | None:
    if response.status_code == 200:
        response_200 = PaginatedMonitoringReportList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedMonitoringReportList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    container_name: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    node: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    source: RtReportsListSource | Unset = UNSET,
    violation: str | Unset = UNSET,
) -> Response[PaginatedMonitoringReportList]:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        cluster (int | Unset):
        container_name (str | Unset):
        limit (int | Unset):
        node (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        source (RtReportsListSource | Unset):
        violation (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedMonitoringReportList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        container_name=container_name,
        limit=limit,
        node=node,
        offset=offset,
        ordering=ordering,
        search=search,
        source=source,
        violation=violation,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    container_name: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    node: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    source: RtReportsListSource | Unset = UNSET,
    violation: str | Unset = UNSET,
) -> PaginatedMonitoringReportList | None:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        cluster (int | Unset):
        container_name (str | Unset):
        limit (int | Unset):
        node (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        source (RtReportsListSource | Unset):
        violation (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedMonitoringReportList
    """

    return sync_detailed(
        client=client,
        cluster=cluster,
        container_name=container_name,
        limit=limit,
        node=node,
        offset=offset,
        ordering=ordering,
        search=search,
        source=source,
        violation=violation,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    container_name: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    node: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    source: RtReportsListSource | Unset = UNSET,
    violation: str | Unset = UNSET,
) -> Response[PaginatedMonitoringReportList]:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        cluster (int | Unset):
        container_name (str | Unset):
        limit (int | Unset):
        node (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        source (RtReportsListSource | Unset):
        violation (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedMonitoringReportList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        container_name=container_name,
        limit=limit,
        node=node,
        offset=offset,
        ordering=ordering,
        search=search,
        source=source,
        violation=violation,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    container_name: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    node: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    source: RtReportsListSource | Unset = UNSET,
    violation: str | Unset = UNSET,
) -> PaginatedMonitoringReportList | None:
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or
    specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node
    taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API
    the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).

    Args:
        cluster (int | Unset):
        container_name (str | Unset):
        limit (int | Unset):
        node (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        source (RtReportsListSource | Unset):
        violation (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedMonitoringReportList
    """

    return (
        await asyncio_detailed(
            client=client,
            cluster=cluster,
            container_name=container_name,
            limit=limit,
            node=node,
            offset=offset,
            ordering=ordering,
            search=search,
            source=source,
            violation=violation,
        )
    ).parsed
