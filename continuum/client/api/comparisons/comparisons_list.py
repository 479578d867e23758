from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_comparison_list_list import PaginatedComparisonListList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    application: int | Unset = UNSET,
    best: str | Unset = UNSET,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["application"] = application

    params["best"] = best

    params["cluster"] = cluster

    params["limit"] = limit

    params["offset"] = offset

    params["ordering"] = ordering

    params["search"] = search

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/comparisons/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedComparisonListList | None:
    if response.status_code == 200:
        response_200 = PaginatedComparisonListList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedComparisonListList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    application: int | Unset = UNSET,
    best: str | Unset = UNSET,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedComparisonListList]:
    """Comparisons of several algorithms on one application (created by ``compare`` jobs); deleting one
    deletes the schedules it made.

    Args:
        application (int | Unset):
        best (str | Unset):
        cluster (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedComparisonListList]
    """

    kwargs = _get_kwargs(
        application=application,
        best=best,
        cluster=cluster,
        limit=limit,
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
    application: int | Unset = UNSET,
    best: str | Unset = UNSET,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedComparisonListList | None:
    """Comparisons of several algorithms on one application (created by ``compare`` jobs); deleting one
    deletes the schedules it made.

    Args:
        application (int | Unset):
        best (str | Unset):
        cluster (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedComparisonListList
    """

    return sync_detailed(
        client=client,
        application=application,
        best=best,
        cluster=cluster,
        limit=limit,
        offset=offset,
        ordering=ordering,
        search=search,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    application: int | Unset = UNSET,
    best: str | Unset = UNSET,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedComparisonListList]:
    """Comparisons of several algorithms on one application (created by ``compare`` jobs); deleting one
    deletes the schedules it made.

    Args:
        application (int | Unset):
        best (str | Unset):
        cluster (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedComparisonListList]
    """

    kwargs = _get_kwargs(
        application=application,
        best=best,
        cluster=cluster,
        limit=limit,
        offset=offset,
        ordering=ordering,
        search=search,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    application: int | Unset = UNSET,
    best: str | Unset = UNSET,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedComparisonListList | None:
    """Comparisons of several algorithms on one application (created by ``compare`` jobs); deleting one
    deletes the schedules it made.

    Args:
        application (int | Unset):
        best (str | Unset):
        cluster (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedComparisonListList
    """

    return (
        await asyncio_detailed(
            client=client,
            application=application,
            best=best,
            cluster=cluster,
            limit=limit,
            offset=offset,
            ordering=ordering,
            search=search,
        )
    ).parsed
