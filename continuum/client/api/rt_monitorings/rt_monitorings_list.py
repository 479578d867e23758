from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_monitoring_list import PaginatedMonitoringList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    cluster: int | Unset = UNSET,
    container_name: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    node_name: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["cluster"] = cluster

    params["container_name"] = container_name

    params["limit"] = limit

    params["node__name"] = node_name

    params["offset"] = offset

    params["ordering"] = ordering

    params["search"] = search

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/rt-monitorings/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedMonitoringList | None:
    if response.status_code == 200:
        response_200 = PaginatedMonitoringList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedMonitoringList]:
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
    node_name: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedMonitoringList]:
    """The latest counters of each monitored container (Listing 3.37).

    Args:
        cluster (int | Unset):
        container_name (str | Unset):
        limit (int | Unset):
        node_name (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedMonitoringList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        container_name=container_name,
        limit=limit,
        node_name=node_name,
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
    cluster: int | Unset = UNSET,
    container_name: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    node_name: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedMonitoringList | None:
    """The latest counters of each monitored container (Listing 3.37).

    Args:
        cluster (int | Unset):
        container_name (str | Unset):
        limit (int | Unset):
        node_name (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedMonitoringList
    """

    return sync_detailed(
        client=client,
        cluster=cluster,
        container_name=container_name,
        limit=limit,
        node_name=node_name,
        offset=offset,
        ordering=ordering,
        search=search,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    container_name: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    node_name: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedMonitoringList]:
    """The latest counters of each monitored container (Listing 3.37).

    Args:
        cluster (int | Unset):
        container_name (str | Unset):
        limit (int | Unset):
        node_name (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedMonitoringList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        container_name=container_name,
        limit=limit,
        node_name=node_name,
        offset=offset,
        ordering=ordering,
        search=search,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    container_name: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    node_name: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedMonitoringList | None:
    """The latest counters of each monitored container (Listing 3.37).

    Args:
        cluster (int | Unset):
        container_name (str | Unset):
        limit (int | Unset):
        node_name (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedMonitoringList
    """

    return (
        await asyncio_detailed(
            client=client,
            cluster=cluster,
            container_name=container_name,
            limit=limit,
            node_name=node_name,
            offset=offset,
            ordering=ordering,
            search=search,
        )
    ).parsed
