from http import HTTPStatus
from typing import Any
from uuid import UUID

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.allocations_list_source import AllocationsListSource
from ...models.paginated_allocation_run_list import PaginatedAllocationRunList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    scenario: str | Unset = UNSET,
    search: str | Unset = UNSET,
    series: UUID | Unset = UNSET,
    source: AllocationsListSource | Unset = UNSET,
    status: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["cluster"] = cluster

    params["limit"] = limit

    params["offset"] = offset

    params["ordering"] = ordering

    params["scenario"] = scenario

    params["search"] = search

    json_series: str | Unset = UNSET
    if not isinstance(series, Unset):
        json_series = str(series)
    params["series"] = json_series

    json_source: str | Unset = UNSET
    if not isinstance(source, Unset):
        json_source = source

    params["source"] = json_source

    params["status"] = status

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/allocations/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedAllocationRunList | None:
    if response.status_code == 200:
        response_200 = PaginatedAllocationRunList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedAllocationRunList]:
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
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    scenario: str | Unset = UNSET,
    search: str | Unset = UNSET,
    series: UUID | Unset = UNSET,
    source: AllocationsListSource | Unset = UNSET,
    status: str | Unset = UNSET,
) -> Response[PaginatedAllocationRunList]:
    """Runs of the monitor-allocation MILP: ``POST`` starts one as a job (with progress), ``simulate``
    runs a thesis case study and stores it as a series of runs.

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        scenario (str | Unset):
        search (str | Unset):
        series (UUID | Unset):
        source (AllocationsListSource | Unset):
        status (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedAllocationRunList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        limit=limit,
        offset=offset,
        ordering=ordering,
        scenario=scenario,
        search=search,
        series=series,
        source=source,
        status=status,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    scenario: str | Unset = UNSET,
    search: str | Unset = UNSET,
    series: UUID | Unset = UNSET,
    source: AllocationsListSource | Unset = UNSET,
    status: str | Unset = UNSET,
) -> PaginatedAllocationRunList | None:
    """Runs of the monitor-allocation MILP: ``POST`` starts one as a job (with progress), ``simulate``
    runs a thesis case study and stores it as a series of runs.

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        scenario (str | Unset):
        search (str | Unset):
        series (UUID | Unset):
        source (AllocationsListSource | Unset):
        status (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedAllocationRunList
    """

    return sync_detailed(
        client=client,
        cluster=cluster,
        limit=limit,
        offset=offset,
        ordering=ordering,
        scenario=scenario,
        search=search,
        series=series,
        source=source,
        status=status,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    scenario: str | Unset = UNSET,
    search: str | Unset = UNSET,
    series: UUID | Unset = UNSET,
    source: AllocationsListSource | Unset = UNSET,
    status: str | Unset = UNSET,
) -> Response[PaginatedAllocationRunList]:
    """Runs of the monitor-allocation MILP: ``POST`` starts one as a job (with progress), ``simulate``
    runs a thesis case study and stores it as a series of runs.

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        scenario (str | Unset):
        search (str | Unset):
        series (UUID | Unset):
        source (AllocationsListSource | Unset):
        status (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedAllocationRunList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        limit=limit,
        offset=offset,
        ordering=ordering,
        scenario=scenario,
        search=search,
        series=series,
        source=source,
        status=status,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    scenario: str | Unset = UNSET,
    search: str | Unset = UNSET,
    series: UUID | Unset = UNSET,
    source: AllocationsListSource | Unset = UNSET,
    status: str | Unset = UNSET,
) -> PaginatedAllocationRunList | None:
    """Runs of the monitor-allocation MILP: ``POST`` starts one as a job (with progress), ``simulate``
    runs a thesis case study and stores it as a series of runs.

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        scenario (str | Unset):
        search (str | Unset):
        series (UUID | Unset):
        source (AllocationsListSource | Unset):
        status (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedAllocationRunList
    """

    return (
        await asyncio_detailed(
            client=client,
            cluster=cluster,
            limit=limit,
            offset=offset,
            ordering=ordering,
            scenario=scenario,
            search=search,
            series=series,
            source=source,
            status=status,
        )
    ).parsed
