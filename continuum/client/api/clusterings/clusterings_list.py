from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_clustering_list_list import PaginatedClusteringListList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    fleet_slug: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rosgraph: int | Unset = UNSET,
    search: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["fleet__slug"] = fleet_slug

    params["limit"] = limit

    params["offset"] = offset

    params["ordering"] = ordering

    params["rosgraph"] = rosgraph

    params["search"] = search

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/clusterings/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedClusteringListList | None:
    if response.status_code == 200:
        response_200 = PaginatedClusteringListList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedClusteringListList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    fleet_slug: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rosgraph: int | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedClusteringListList]:
    """Results of clustering jobs: containers with their ROS nodes, bandwidth, image plan and disk figures.

    Args:
        fleet_slug (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rosgraph (int | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedClusteringListList]
    """

    kwargs = _get_kwargs(
        fleet_slug=fleet_slug,
        limit=limit,
        offset=offset,
        ordering=ordering,
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
    fleet_slug: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rosgraph: int | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedClusteringListList | None:
    """Results of clustering jobs: containers with their ROS nodes, bandwidth, image plan and disk figures.

    Args:
        fleet_slug (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rosgraph (int | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedClusteringListList
    """

    return sync_detailed(
        client=client,
        fleet_slug=fleet_slug,
        limit=limit,
        offset=offset,
        ordering=ordering,
        rosgraph=rosgraph,
        search=search,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    fleet_slug: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rosgraph: int | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedClusteringListList]:
    """Results of clustering jobs: containers with their ROS nodes, bandwidth, image plan and disk figures.

    Args:
        fleet_slug (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rosgraph (int | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedClusteringListList]
    """

    kwargs = _get_kwargs(
        fleet_slug=fleet_slug,
        limit=limit,
        offset=offset,
        ordering=ordering,
        rosgraph=rosgraph,
        search=search,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    fleet_slug: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rosgraph: int | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedClusteringListList | None:
    """Results of clustering jobs: containers with their ROS nodes, bandwidth, image plan and disk figures.

    Args:
        fleet_slug (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rosgraph (int | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedClusteringListList
    """

    return (
        await asyncio_detailed(
            client=client,
            fleet_slug=fleet_slug,
            limit=limit,
            offset=offset,
            ordering=ordering,
            rosgraph=rosgraph,
            search=search,
        )
    ).parsed
