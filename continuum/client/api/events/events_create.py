from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.event_batch import EventBatch
from ...models.event_batch_request import EventBatchRequest
from ...types import Response


def _get_kwargs(
    *,
    body: EventBatchRequest,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/events/",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> EventBatch | None:
    if response.status_code == 201:
        response_201 = EventBatch.from_dict(response.json())

        return response_201

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[EventBatch]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: EventBatchRequest,
) -> Response[EventBatch]:
    """With a handler of the cluster running, the batch goes to the handlers' Redis event stream (202);
    otherwise the cluster's monitors evaluate it here (200, with the violations found).

    Args:
        body (EventBatchRequest): Events of the system under verification: ``[variable, value,
            timestamp_ms]`` triples (or objects with
            those keys), for one cluster; ``now`` (ms, optional) also advances the monitors' clock.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[EventBatch]
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
    body: EventBatchRequest,
) -> EventBatch | None:
    """With a handler of the cluster running, the batch goes to the handlers' Redis event stream (202);
    otherwise the cluster's monitors evaluate it here (200, with the violations found).

    Args:
        body (EventBatchRequest): Events of the system under verification: ``[variable, value,
            timestamp_ms]`` triples (or objects with
            those keys), for one cluster; ``now`` (ms, optional) also advances the monitors' clock.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        EventBatch
    """

    return sync_detailed(
        client=client,
        body=body,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: EventBatchRequest,
) -> Response[EventBatch]:
    """With a handler of the cluster running, the batch goes to the handlers' Redis event stream (202);
    otherwise the cluster's monitors evaluate it here (200, with the violations found).

    Args:
        body (EventBatchRequest): Events of the system under verification: ``[variable, value,
            timestamp_ms]`` triples (or objects with
            those keys), for one cluster; ``now`` (ms, optional) also advances the monitors' clock.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[EventBatch]
    """

    kwargs = _get_kwargs(
        body=body,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    body: EventBatchRequest,
) -> EventBatch | None:
    """With a handler of the cluster running, the batch goes to the handlers' Redis event stream (202);
    otherwise the cluster's monitors evaluate it here (200, with the violations found).

    Args:
        body (EventBatchRequest): Events of the system under verification: ``[variable, value,
            timestamp_ms]`` triples (or objects with
            those keys), for one cluster; ``now`` (ms, optional) also advances the monitors' clock.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        EventBatch
    """

    return (
        await asyncio_detailed(
            client=client,
            body=body,
        )
    ).parsed
