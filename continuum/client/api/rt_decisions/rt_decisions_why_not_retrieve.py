from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.why_not import WhyNot
from ...types import UNSET, Response, Unset


def _get_kwargs(
    id: int,
    *,
    node: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["node"] = node

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/rt-decisions/{id}/why-not/".format(
            id=quote(str(id), safe=""),
        ),
        "params": params,
    }

    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> WhyNot | None:
    if response.status_code == 200:
        response_200 = WhyNot.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[WhyNot]:
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
    node: str | Unset = UNSET,
) -> Response[WhyNot]:
    """Why not this node? The pod's verdict on one node (``?node=``) or on every node of the cluster, by
    the scheduler's filters and scores, against the cluster as it is now (400: no such node).

    Args:
        id (int):
        node (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[WhyNot]
    """

    kwargs = _get_kwargs(
        id=id,
        node=node,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    id: int,
    *,
    client: AuthenticatedClient,
    node: str | Unset = UNSET,
) -> WhyNot | None:
    """Why not this node? The pod's verdict on one node (``?node=``) or on every node of the cluster, by
    the scheduler's filters and scores, against the cluster as it is now (400: no such node).

    Args:
        id (int):
        node (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        WhyNot
    """

    return sync_detailed(
        id=id,
        client=client,
        node=node,
    ).parsed


async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
    node: str | Unset = UNSET,
) -> Response[WhyNot]:
    """Why not this node? The pod's verdict on one node (``?node=``) or on every node of the cluster, by
    the scheduler's filters and scores, against the cluster as it is now (400: no such node).

    Args:
        id (int):
        node (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[WhyNot]
    """

    kwargs = _get_kwargs(
        id=id,
        node=node,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
    node: str | Unset = UNSET,
) -> WhyNot | None:
    """Why not this node? The pod's verdict on one node (``?node=``) or on every node of the cluster, by
    the scheduler's filters and scores, against the cluster as it is now (400: no such node).

    Args:
        id (int):
        node (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        WhyNot
    """

    return (
        await asyncio_detailed(
            id=id,
            client=client,
            node=node,
        )
    ).parsed
