from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.monitor import Monitor
from ...models.monitor_request import MonitorRequest
from ...types import Response


def _get_kwargs(
    *,
    body: MonitorRequest,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/monitors/",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Monitor | None:
    if response.status_code == 201:
        response_201 = Monitor.from_dict(response.json())

        return response_201

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[Monitor]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: MonitorRequest,
) -> Response[Monitor]:
    """Monitors of assertions on a cluster; ``node`` is the node whose handler runs it.

    Args:
        body (MonitorRequest): ``fleet`` defaults to the token's fleet, or to the caller's only
            fleet.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Monitor]
    """

    kwargs = _get_kwargs(
        body=body,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    body: MonitorRequest,
) -> Monitor | None:
    """Monitors of assertions on a cluster; ``node`` is the node whose handler runs it.

    Args:
        body (MonitorRequest): ``fleet`` defaults to the token's fleet, or to the caller's only
            fleet.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Monitor
    """

    return sync_detailed(
        client=client,
        body=body,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: MonitorRequest,
) -> Response[Monitor]:
    """Monitors of assertions on a cluster; ``node`` is the node whose handler runs it.

    Args:
        body (MonitorRequest): ``fleet`` defaults to the token's fleet, or to the caller's only
            fleet.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Monitor]
    """

    kwargs = _get_kwargs(
        body=body,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    body: MonitorRequest,
) -> Monitor | None:
    """Monitors of assertions on a cluster; ``node`` is the node whose handler runs it.

    Args:
        body (MonitorRequest): ``fleet`` defaults to the token's fleet, or to the caller's only
            fleet.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Monitor
    """

    return (
        await asyncio_detailed(
            client=client,
            body=body,
        )
    ).parsed
