from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.placements_why_retrieve_response_200 import PlacementsWhyRetrieveResponse200
from ...types import UNSET, Response, Unset


def _get_kwargs(
    id: int,
    *,
    container: str | Unset = UNSET,
    full: bool | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["container"] = container

    params["full"] = full

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/placements/{id}/why/".format(
            id=quote(str(id), safe=""),
        ),
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PlacementsWhyRetrieveResponse200 | None:
    if response.status_code == 200:
        response_200 = PlacementsWhyRetrieveResponse200.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PlacementsWhyRetrieveResponse200]:
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
    container: str | Unset = UNSET,
    full: bool | Unset = UNSET,
) -> Response[PlacementsWhyRetrieveResponse200]:
    """Why each container went where it went: per node, the rejecting filter and reason, or each
    scoring policy's score and the total (like kube-scheduler-simulator). Stored bounded (the best
    candidates, nodes per filter in ``rejections``, an example each); ``container`` with ``full=1``:
    every node's verdict, recomputed from the placement's stored inputs.

    Args:
        id (int):
        container (str | Unset):
        full (bool | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PlacementsWhyRetrieveResponse200]
    """

    kwargs = _get_kwargs(
        id=id,
        container=container,
        full=full,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    id: int,
    *,
    client: AuthenticatedClient,
    container: str | Unset = UNSET,
    full: bool | Unset = UNSET,
) -> PlacementsWhyRetrieveResponse200 | None:
    """Why each container went where it went: per node, the rejecting filter and reason, or each
    scoring policy's score and the total (like kube-scheduler-simulator). Stored bounded (the best
    candidates, nodes per filter in ``rejections``, an example each); ``container`` with ``full=1``:
    every node's verdict, recomputed from the placement's stored inputs.

    Args:
        id (int):
        container (str | Unset):
        full (bool | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PlacementsWhyRetrieveResponse200
    """

    return sync_detailed(
        id=id,
        client=client,
        container=container,
        full=full,
    ).parsed


async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
    container: str | Unset = UNSET,
    full: bool | Unset = UNSET,
) -> Response[PlacementsWhyRetrieveResponse200]:
    """Why each container went where it went: per node, the rejecting filter and reason, or each
    scoring policy's score and the total (like kube-scheduler-simulator). Stored bounded (the best
    candidates, nodes per filter in ``rejections``, an example each); ``container`` with ``full=1``:
    every node's verdict, recomputed from the placement's stored inputs.

    Args:
        id (int):
        container (str | Unset):
        full (bool | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PlacementsWhyRetrieveResponse200]
    """

    kwargs = _get_kwargs(
        id=id,
        container=container,
        full=full,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
    container: str | Unset = UNSET,
    full: bool | Unset = UNSET,
) -> PlacementsWhyRetrieveResponse200 | None:
    """Why each container went where it went: per node, the rejecting filter and reason, or each
    scoring policy's score and the total (like kube-scheduler-simulator). Stored bounded (the best
    candidates, nodes per filter in ``rejections``, an example each); ``container`` with ``full=1``:
    every node's verdict, recomputed from the placement's stored inputs.

    Args:
        id (int):
        container (str | Unset):
        full (bool | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PlacementsWhyRetrieveResponse200
    """

    return (
        await asyncio_detailed(
            id=id,
            client=client,
            container=container,
            full=full,
        )
    ).parsed
