from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_node_admission_list import PaginatedNodeAdmissionList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    name: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rt: bool | Unset = UNSET,
    search: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["cluster"] = cluster

    params["limit"] = limit

    params["name"] = name

    params["offset"] = offset

    params["ordering"] = ordering

    params["rt"] = rt

    params["search"] = search

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/rt-admissions/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedNodeAdmissionList | None:
    if response.status_code == 200:
        response_200 = PaginatedNodeAdmissionList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedNodeAdmissionList]:
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
    name: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rt: bool | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedNodeAdmissionList]:
    """Each node's admissible RT bandwidth and where it comes from. POST (a node agent, with a robot
    token):
    ``{"cluster": id, "node": name, "capacity": CPUs, "cpus": [...], "source": "...", "kernel":
    "..."}``, what
    ``python -m continuum.agent admission`` read from the node's kernel. RT-Kube's filter then admits up
    to it,
    unless the cluster file gives the node an ``rt_threshold`` (which wins); a node that reported
    nothing keeps
    the thesis' M x 0.95 (``rt_capacity_source`` says which).

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        name (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rt (bool | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedNodeAdmissionList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        limit=limit,
        name=name,
        offset=offset,
        ordering=ordering,
        rt=rt,
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
    limit: int | Unset = UNSET,
    name: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rt: bool | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedNodeAdmissionList | None:
    """Each node's admissible RT bandwidth and where it comes from. POST (a node agent, with a robot
    token):
    ``{"cluster": id, "node": name, "capacity": CPUs, "cpus": [...], "source": "...", "kernel":
    "..."}``, what
    ``python -m continuum.agent admission`` read from the node's kernel. RT-Kube's filter then admits up
    to it,
    unless the cluster file gives the node an ``rt_threshold`` (which wins); a node that reported
    nothing keeps
    the thesis' M x 0.95 (``rt_capacity_source`` says which).

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        name (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rt (bool | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedNodeAdmissionList
    """

    return sync_detailed(
        client=client,
        cluster=cluster,
        limit=limit,
        name=name,
        offset=offset,
        ordering=ordering,
        rt=rt,
        search=search,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    name: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rt: bool | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedNodeAdmissionList]:
    """Each node's admissible RT bandwidth and where it comes from. POST (a node agent, with a robot
    token):
    ``{"cluster": id, "node": name, "capacity": CPUs, "cpus": [...], "source": "...", "kernel":
    "..."}``, what
    ``python -m continuum.agent admission`` read from the node's kernel. RT-Kube's filter then admits up
    to it,
    unless the cluster file gives the node an ``rt_threshold`` (which wins); a node that reported
    nothing keeps
    the thesis' M x 0.95 (``rt_capacity_source`` says which).

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        name (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rt (bool | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedNodeAdmissionList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        limit=limit,
        name=name,
        offset=offset,
        ordering=ordering,
        rt=rt,
        search=search,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    name: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    rt: bool | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedNodeAdmissionList | None:
    """Each node's admissible RT bandwidth and where it comes from. POST (a node agent, with a robot
    token):
    ``{"cluster": id, "node": name, "capacity": CPUs, "cpus": [...], "source": "...", "kernel":
    "..."}``, what
    ``python -m continuum.agent admission`` read from the node's kernel. RT-Kube's filter then admits up
    to it,
    unless the cluster file gives the node an ``rt_threshold`` (which wins); a node that reported
    nothing keeps
    the thesis' M x 0.95 (``rt_capacity_source`` says which).

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        name (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        rt (bool | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedNodeAdmissionList
    """

    return (
        await asyncio_detailed(
            client=client,
            cluster=cluster,
            limit=limit,
            name=name,
            offset=offset,
            ordering=ordering,
            rt=rt,
            search=search,
        )
    ).parsed
