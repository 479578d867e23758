from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_ros_graph_list_list import PaginatedRosGraphListList
from ...models.rosgraphs_list_source_format import RosgraphsListSourceFormat
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    fleet_slug: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    source_format: RosgraphsListSourceFormat | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["fleet__slug"] = fleet_slug

    params["limit"] = limit

    params["offset"] = offset

    params["ordering"] = ordering

    params["search"] = search

    json_source_format: str | Unset = UNSET
    if not isinstance(source_format, Unset):
        json_source_format = source_format

    params["source_format"] = json_source_format

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/rosgraphs/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedRosGraphListList | None:
    if response.status_code == 200:
        response_200 = PaginatedRosGraphListList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedRosGraphListList]:
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
    search: str | Unset = UNSET,
    source_format: RosgraphsListSourceFormat | Unset = UNSET,
) -> Response[PaginatedRosGraphListList]:
    """ROS computation graphs. Create them with ``import``; PATCH edits levels, rates and message sizes.

    Args:
        fleet_slug (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        source_format (RosgraphsListSourceFormat | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedRosGraphListList]
    """

    kwargs = _get_kwargs(
        fleet_slug=fleet_slug,
        limit=limit,
        offset=offset,
        ordering=ordering,
        search=search,
        source_format=source_format,
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
    search: str | Unset = UNSET,
    source_format: RosgraphsListSourceFormat | Unset = UNSET,
) -> PaginatedRosGraphListList | None:
    """ROS computation graphs. Create them with ``import``; PATCH edits levels, rates and message sizes.

    Args:
        fleet_slug (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        source_format (RosgraphsListSourceFormat | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedRosGraphListList
    """

    return sync_detailed(
        client=client,
        fleet_slug=fleet_slug,
        limit=limit,
        offset=offset,
        ordering=ordering,
        search=search,
        source_format=source_format,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    fleet_slug: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    source_format: RosgraphsListSourceFormat | Unset = UNSET,
) -> Response[PaginatedRosGraphListList]:
    """ROS computation graphs. Create them with ``import``; PATCH edits levels, rates and message sizes.

    Args:
        fleet_slug (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        source_format (RosgraphsListSourceFormat | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedRosGraphListList]
    """

    kwargs = _get_kwargs(
        fleet_slug=fleet_slug,
        limit=limit,
        offset=offset,
        ordering=ordering,
        search=search,
        source_format=source_format,
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
    search: str | Unset = UNSET,
    source_format: RosgraphsListSourceFormat | Unset = UNSET,
) -> PaginatedRosGraphListList | None:
    """ROS computation graphs. Create them with ``import``; PATCH edits levels, rates and message sizes.

    Args:
        fleet_slug (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        source_format (RosgraphsListSourceFormat | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedRosGraphListList
    """

    return (
        await asyncio_detailed(
            client=client,
            fleet_slug=fleet_slug,
            limit=limit,
            offset=offset,
            ordering=ordering,
            search=search,
            source_format=source_format,
        )
    ).parsed
