from http import HTTPStatus
from typing import Any
from uuid import UUID

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_migration_event_list import PaginatedMigrationEventList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    run: int | Unset = UNSET,
    run_series: UUID | Unset = UNSET,
    search: str | Unset = UNSET,
    source: str | Unset = UNSET,
    target: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["limit"] = limit

    params["monitor"] = monitor

    params["offset"] = offset

    params["ordering"] = ordering

    params["run"] = run

    json_run_series: str | Unset = UNSET
    if not isinstance(run_series, Unset):
        json_run_series = str(run_series)
    params["run__series"] = json_run_series

    params["search"] = search

    params["source"] = source

    params["target"] = target

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/migrations/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedMigrationEventList | None:
    if response.status_code == 200:
        response_200 = PaginatedMigrationEventList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedMigrationEventList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    run: int | Unset = UNSET,
    run_series: UUID | Unset = UNSET,
    search: str | Unset = UNSET,
    source: str | Unset = UNSET,
    target: str | Unset = UNSET,
) -> Response[PaginatedMigrationEventList]:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        limit (int | Unset):
        monitor (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        run (int | Unset):
        run_series (UUID | Unset):
        search (str | Unset):
        source (str | Unset):
        target (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedMigrationEventList]
    """

    kwargs = _get_kwargs(
        limit=limit,
        monitor=monitor,
        offset=offset,
        ordering=ordering,
        run=run,
        run_series=run_series,
        search=search,
        source=source,
        target=target,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    run: int | Unset = UNSET,
    run_series: UUID | Unset = UNSET,
    search: str | Unset = UNSET,
    source: str | Unset = UNSET,
    target: str | Unset = UNSET,
) -> PaginatedMigrationEventList | None:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        limit (int | Unset):
        monitor (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        run (int | Unset):
        run_series (UUID | Unset):
        search (str | Unset):
        source (str | Unset):
        target (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedMigrationEventList
    """

    return sync_detailed(
        client=client,
        limit=limit,
        monitor=monitor,
        offset=offset,
        ordering=ordering,
        run=run,
        run_series=run_series,
        search=search,
        source=source,
        target=target,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    run: int | Unset = UNSET,
    run_series: UUID | Unset = UNSET,
    search: str | Unset = UNSET,
    source: str | Unset = UNSET,
    target: str | Unset = UNSET,
) -> Response[PaginatedMigrationEventList]:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        limit (int | Unset):
        monitor (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        run (int | Unset):
        run_series (UUID | Unset):
        search (str | Unset):
        source (str | Unset):
        target (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedMigrationEventList]
    """

    kwargs = _get_kwargs(
        limit=limit,
        monitor=monitor,
        offset=offset,
        ordering=ordering,
        run=run,
        run_series=run_series,
        search=search,
        source=source,
        target=target,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    run: int | Unset = UNSET,
    run_series: UUID | Unset = UNSET,
    search: str | Unset = UNSET,
    source: str | Unset = UNSET,
    target: str | Unset = UNSET,
) -> PaginatedMigrationEventList | None:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        limit (int | Unset):
        monitor (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        run (int | Unset):
        run_series (UUID | Unset):
        search (str | Unset):
        source (str | Unset):
        target (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedMigrationEventList
    """

    return (
        await asyncio_detailed(
            client=client,
            limit=limit,
            monitor=monitor,
            offset=offset,
            ordering=ordering,
            run=run,
            run_series=run_series,
            search=search,
            source=source,
            target=target,
        )
    ).parsed
