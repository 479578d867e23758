from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.node_admission import NodeAdmission
from ...types import Response


def _get_kwargs(
    id: int,
) -> dict[str, Any]:

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/rt-admissions/{id}/".format(
            id=quote(str(id), safe=""),
        ),
    }

    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> NodeAdmission | None:
    if response.status_code == 200:
        response_200 = NodeAdmission.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[NodeAdmission]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
) -> Response[NodeAdmission]:
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
        id (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[NodeAdmission]
    """

    kwargs = _get_kwargs(
        id=id,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    id: int,
    *,
    client: AuthenticatedClient,
) -> NodeAdmission | None:
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
        id (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        NodeAdmission
    """

    return sync_detailed(
        id=id,
        client=client,
    ).parsed


async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
) -> Response[NodeAdmission]:
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
        id (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[NodeAdmission]
    """

    kwargs = _get_kwargs(
        id=id,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
) -> NodeAdmission | None:
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
        id (int):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        NodeAdmission
    """

    return (
        await asyncio_detailed(
            id=id,
            client=client,
        )
    ).parsed
