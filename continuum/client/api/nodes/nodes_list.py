from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.nodes_list_arch import NodesListArch
from ...models.nodes_list_criticality import NodesListCriticality
from ...models.nodes_list_status import NodesListStatus
from ...models.paginated_compute_node_list import PaginatedComputeNodeList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    arch: NodesListArch | Unset = UNSET,
    cluster: int | Unset = UNSET,
    criticality: NodesListCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rt: bool | Unset = UNSET,
    search: str | Unset = UNSET,
    status: NodesListStatus | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    json_arch: str | Unset = UNSET
    if not isinstance(arch, Unset):
        json_arch = arch

    params["arch"] = json_arch

    params["cluster"] = cluster

    json_criticality: str | Unset = UNSET
    if not isinstance(criticality, Unset):
        json_criticality = criticality

    params["criticality"] = json_criticality

    params["limit"] = limit

    params["offset"] = offset

    params["ordering"] = ordering

    params["rt"] = rt

    params["search"] = search

    json_status: str | Unset = UNSET
    if not isinstance(status, Unset):
        json_status = status

    params["status"] = json_status

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/nodes/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedComputeNodeList | None:
    if response.status_code == 200:
        response_200 = PaginatedComputeNodeList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedComputeNodeList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    arch: NodesListArch | Unset = UNSET,
    cluster: int | Unset = UNSET,
    criticality: NodesListCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rt: bool | Unset = UNSET,
    search: str | Unset = UNSET,
    status: NodesListStatus | Unset = UNSET,
) -> Response[PaginatedComputeNodeList]:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        arch (NodesListArch | Unset):
        cluster (int | Unset):
        criticality (NodesListCriticality | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rt (bool | Unset):
        search (str | Unset):
        status (NodesListStatus | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedComputeNodeList]
    """

    kwargs = _get_kwargs(
        arch=arch,
        cluster=cluster,
        criticality=criticality,
        limit=limit,
        offset=offset,
        ordering=ordering,
        rt=rt,
        search=search,
        status=status,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    arch: NodesListArch | Unset = UNSET,
    cluster: int | Unset = UNSET,
    criticality: NodesListCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rt: bool | Unset = UNSET,
    search: str | Unset = UNSET,
    status: NodesListStatus | Unset = UNSET,
) -> PaginatedComputeNodeList | None:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        arch (NodesListArch | Unset):
        cluster (int | Unset):
        criticality (NodesListCriticality | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rt (bool | Unset):
        search (str | Unset):
        status (NodesListStatus | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedComputeNodeList
    """

    return sync_detailed(
        client=client,
        arch=arch,
        cluster=cluster,
        criticality=criticality,
        limit=limit,
        offset=offset,
        ordering=ordering,
        rt=rt,
        search=search,
        status=status,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    arch: NodesListArch | Unset = UNSET,
    cluster: int | Unset = UNSET,
    criticality: NodesListCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rt: bool | Unset = UNSET,
    search: str | Unset = UNSET,
    status: NodesListStatus | Unset = UNSET,
) -> Response[PaginatedComputeNodeList]:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        arch (NodesListArch | Unset):
        cluster (int | Unset):
        criticality (NodesListCriticality | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rt (bool | Unset):
        search (str | Unset):
        status (NodesListStatus | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedComputeNodeList]
    """

    kwargs = _get_kwargs(
        arch=arch,
        cluster=cluster,
        criticality=criticality,
        limit=limit,
        offset=offset,
        ordering=ordering,
        rt=rt,
        search=search,
        status=status,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    arch: NodesListArch | Unset = UNSET,
    cluster: int | Unset = UNSET,
    criticality: NodesListCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rt: bool | Unset = UNSET,
    search: str | Unset = UNSET,
    status: NodesListStatus | Unset = UNSET,
) -> PaginatedComputeNodeList | None:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        arch (NodesListArch | Unset):
        cluster (int | Unset):
        criticality (NodesListCriticality | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rt (bool | Unset):
        search (str | Unset):
        status (NodesListStatus | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedComputeNodeList
    """

    return (
        await asyncio_detailed(
            client=client,
            arch=arch,
            cluster=cluster,
            criticality=criticality,
            limit=limit,
            offset=offset,
            ordering=ordering,
            rt=rt,
            search=search,
            status=status,
        )
    ).parsed
