from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_violation_list import PaginatedViolationList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    handler: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    monitor_assertion: int | Unset = UNSET,
    monitor_cluster: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["handler"] = handler

    params["limit"] = limit

    params["monitor"] = monitor

    params["monitor__assertion"] = monitor_assertion

    params["monitor__cluster"] = monitor_cluster

    params["offset"] = offset

    params["ordering"] = ordering

    params["search"] = search

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/violations/",
        "params": params,
    }

    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> PaginatedViolationList | None:
    if response.status_code == 200:
        response_200 = PaginatedViolationList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedViolationList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    handler: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    monitor_assertion: int | Unset = UNSET,
    monitor_cluster: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedViolationList]:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        handler (str | Unset):
        limit (int | Unset):
        monitor (int | Unset):
        monitor_assertion (int | Unset):
        monitor_cluster (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedViolationList]
    """

    kwargs = _get_kwargs(
        handler=handler,
        limit=limit,
        monitor=monitor,
        monitor_assertion=monitor_assertion,
        monitor_cluster=monitor_cluster,
        offset=offset,
        ordering=ordering,
        search=search,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    handler: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    monitor_assertion: int | Unset = UNSET,
    monitor_cluster: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedViolationList | None:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        handler (str | Unset):
        limit (int | Unset):
        monitor (int | Unset):
        monitor_assertion (int | Unset):
        monitor_cluster (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedViolationList
    """

    return sync_detailed(
        client=client,
        handler=handler,
        limit=limit,
        monitor=monitor,
        monitor_assertion=monitor_assertion,
        monitor_cluster=monitor_cluster,
        offset=offset,
        ordering=ordering,
        search=search,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    handler: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    monitor_assertion: int | Unset = UNSET,
    monitor_cluster: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedViolationList]:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        handler (str | Unset):
        limit (int | Unset):
        monitor (int | Unset):
        monitor_assertion (int | Unset):
        monitor_cluster (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedViolationList]
    """

    kwargs = _get_kwargs(
        handler=handler,
        limit=limit,
        monitor=monitor,
        monitor_assertion=monitor_assertion,
        monitor_cluster=monitor_cluster,
        offset=offset,
        ordering=ordering,
        search=search,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    handler: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    monitor_assertion: int | Unset = UNSET,
    monitor_cluster: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedViolationList | None:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        handler (str | Unset):
        limit (int | Unset):
        monitor (int | Unset):
        monitor_assertion (int | Unset):
        monitor_cluster (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedViolationList
    """

    return (
        await asyncio_detailed(
            client=client,
            handler=handler,
            limit=limit,
            monitor=monitor,
            monitor_assertion=monitor_assertion,
            monitor_cluster=monitor_cluster,
            offset=offset,
            ordering=ordering,
            search=search,
        )
    ).parsed
