from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.devices_thresholds_create_response_200 import DevicesThresholdsCreateResponse200
from ...models.thresholds_request_request import ThresholdsRequestRequest
from ...types import Response


def _get_kwargs(
    slug: str,
    *,
    body: ThresholdsRequestRequest,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/devices/{slug}/thresholds/".format(
            slug=quote(str(slug), safe=""),
        ),
    }

    _kwargs["files"] = body.to_multipart()

    headers["Content-Type"] = "multipart/form-data; boundary=+++"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> DevicesThresholdsCreateResponse200 | None:
    if response.status_code == 200:
        response_200 = DevicesThresholdsCreateResponse200.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[DevicesThresholdsCreateResponse200]:
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
    body: ThresholdsRequestRequest,
) -> Response[DevicesThresholdsCreateResponse200]:
    """GPU cache thresholds extracted from a micro-benchmark CSV (spec 01 section 9.6); the profile is not
    changed (administrators apply them in the admin).

    Args:
        slug (str): the device id, e.g. jetson-tx2
        body (ThresholdsRequestRequest): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[DevicesThresholdsCreateResponse200]
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
    body: ThresholdsRequestRequest,
) -> DevicesThresholdsCreateResponse200 | None:
    """GPU cache thresholds extracted from a micro-benchmark CSV (spec 01 section 9.6); the profile is not
    changed (administrators apply them in the admin).

    Args:
        slug (str): the device id, e.g. jetson-tx2
        body (ThresholdsRequestRequest): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        DevicesThresholdsCreateResponse200
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
    body: ThresholdsRequestRequest,
) -> Response[DevicesThresholdsCreateResponse200]:
    """GPU cache thresholds extracted from a micro-benchmark CSV (spec 01 section 9.6); the profile is not
    changed (administrators apply them in the admin).

    Args:
        slug (str): the device id, e.g. jetson-tx2
        body (ThresholdsRequestRequest): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[DevicesThresholdsCreateResponse200]
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
    body: ThresholdsRequestRequest,
) -> DevicesThresholdsCreateResponse200 | None:
    """GPU cache thresholds extracted from a micro-benchmark CSV (spec 01 section 9.6); the profile is not
    changed (administrators apply them in the admin).

    Args:
        slug (str): the device id, e.g. jetson-tx2
        body (ThresholdsRequestRequest): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        DevicesThresholdsCreateResponse200
    """

    return (
        await asyncio_detailed(
            slug=slug,
            client=client,
            body=body,
        )
    ).parsed
