from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_placement_list_list import PaginatedPlacementListList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    cluster: int | Unset = UNSET,
    clustering: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    policy: str | Unset = UNSET,
    rosgraph: int | Unset = UNSET,
    search: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["cluster"] = cluster

    params["clustering"] = clustering

    params["limit"] = limit

    params["offset"] = offset

    params["ordering"] = ordering

    params["policy"] = policy

    params["rosgraph"] = rosgraph

    params["search"] = search

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/placements/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedPlacementListList | None:
    if response.status_code == 200:
        response_200 = PaginatedPlacementListList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedPlacementListList]:
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
    clustering: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    policy: str | Unset = UNSET,
    rosgraph: int | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedPlacementListList]:
    """Placements of containers on nodes, every node's verdict for every container, and their push.

    Args:
        cluster (int | Unset):
        clustering (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        policy (str | Unset):
        rosgraph (int | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedPlacementListList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        clustering=clustering,
        limit=limit,
        offset=offset,
        ordering=ordering,
        policy=policy,
        rosgraph=rosgraph,
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
    clustering: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    policy: str | Unset = UNSET,
    rosgraph: int | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedPlacementListList | None:
    """Placements of containers on nodes, every node's verdict for every container, and their push.

    Args:
        cluster (int | Unset):
        clustering (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        policy (str | Unset):
        rosgraph (int | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedPlacementListList
    """

    return sync_detailed(
        client=client,
        cluster=cluster,
        clustering=clustering,
        limit=limit,
        offset=offset,
        ordering=ordering,
        policy=policy,
        rosgraph=rosgraph,
        search=search,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    clustering: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    policy: str | Unset = UNSET,
    rosgraph: int | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedPlacementListList]:
    """Placements of containers on nodes, every node's verdict for every container, and their push.

    Args:
        cluster (int | Unset):
        clustering (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        policy (str | Unset):
        rosgraph (int | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedPlacementListList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        clustering=clustering,
        limit=limit,
        offset=offset,
        ordering=ordering,
        policy=policy,
        rosgraph=rosgraph,
        search=search,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    clustering: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    policy: str | Unset = UNSET,
    rosgraph: int | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedPlacementListList | None:
    """Placements of containers on nodes, every node's verdict for every container, and their push.

    Args:
        cluster (int | Unset):
        clustering (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        policy (str | Unset):
        rosgraph (int | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedPlacementListList
    """

    return (
        await asyncio_detailed(
            client=client,
            cluster=cluster,
            clustering=clustering,
            limit=limit,
            offset=offset,
            ordering=ordering,
            policy=policy,
            rosgraph=rosgraph,
            search=search,
        )
    ).parsed
