from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.advice_request_request import AdviceRequestRequest
from ...models.devices_advise_create_response_200 import DevicesAdviseCreateResponse200
from ...types import UNSET, Response, Unset


def _get_kwargs(
    slug: str,
    *,
    body: AdviceRequestRequest | Unset = UNSET,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/devices/{slug}/advise/".format(
            slug=quote(str(slug), safe=""),
        ),
    }

    if not isinstance(body, Unset):
        _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> DevicesAdviseCreateResponse200 | None:
    if response.status_code == 200:
        response_200 = DevicesAdviseCreateResponse200.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[DevicesAdviseCreateResponse200]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    slug: str,
    *,
    client: AuthenticatedClient,
    body: AdviceRequestRequest | Unset = UNSET,
) -> Response[DevicesAdviseCreateResponse200]:
    """Recommend standard copy, unified memory or zero copy for an application profiled on this board,
    with the predicted speedup (Eqs. 3.10-3.11) and the ROS transport to use (ROS-SC / ROS-SHM-ZC...).

    Args:
        slug (str): the device id, e.g. jetson-tx2
        body (AdviceRequestRequest | Unset): An application's profile on this board (Eqs. 3.8-3.9
            inputs, runtimes for Eqs. 3.10-3.11) and how its
            ROS nodes share the buffer (thesis 3.1.3).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[DevicesAdviseCreateResponse200]
    """

    kwargs = _get_kwargs(
        slug=slug,
        body=body,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    slug: str,
    *,
    client: AuthenticatedClient,
    body: AdviceRequestRequest | Unset = UNSET,
) -> DevicesAdviseCreateResponse200 | None:
    """Recommend standard copy, unified memory or zero copy for an application profiled on this board,
    with the predicted speedup (Eqs. 3.10-3.11) and the ROS transport to use (ROS-SC / ROS-SHM-ZC...).

    Args:
        slug (str): the device id, e.g. jetson-tx2
        body (AdviceRequestRequest | Unset): An application's profile on this board (Eqs. 3.8-3.9
            inputs, runtimes for Eqs. 3.10-3.11) and how its
            ROS nodes share the buffer (thesis 3.1.3).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        DevicesAdviseCreateResponse200
    """

    return sync_detailed(
        slug=slug,
        client=client,
        body=body,
    ).parsed


async def asyncio_detailed(
    slug: str,
    *,
    client: AuthenticatedClient,
    body: AdviceRequestRequest | Unset = UNSET,
) -> Response[DevicesAdviseCreateResponse200]:
    """Recommend standard copy, unified memory or zero copy for an application profiled on this board,
    with the predicted speedup (Eqs. 3.10-3.11) and the ROS transport to use (ROS-SC / ROS-SHM-ZC...).

    Args:
        slug (str): the device id, e.g. jetson-tx2
        body (AdviceRequestRequest | Unset): An application's profile on this board (Eqs. 3.8-3.9
            inputs, runtimes for Eqs. 3.10-3.11) and how its
            ROS nodes share the buffer (thesis 3.1.3).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[DevicesAdviseCreateResponse200]
    """

    kwargs = _get_kwargs(
        slug=slug,
        body=body,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    slug: str,
    *,
    client: AuthenticatedClient,
    body: AdviceRequestRequest | Unset = UNSET,
) -> DevicesAdviseCreateResponse200 | None:
    """Recommend standard copy, unified memory or zero copy for an application profiled on this board,
    with the predicted speedup (Eqs. 3.10-3.11) and the ROS transport to use (ROS-SC / ROS-SHM-ZC...).

    Args:
        slug (str): the device id, e.g. jetson-tx2
        body (AdviceRequestRequest | Unset): An application's profile on this board (Eqs. 3.8-3.9
            inputs, runtimes for Eqs. 3.10-3.11) and how its
            ROS nodes share the buffer (thesis 3.1.3).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        DevicesAdviseCreateResponse200
    """

    return (
        await asyncio_detailed(
            slug=slug,
            client=client,
            body=body,
        )
    ).parsed
