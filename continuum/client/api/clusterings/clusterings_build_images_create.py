from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.build_images_request_request import BuildImagesRequestRequest
from ...models.job import Job
from ...types import UNSET, Response, Unset


def _get_kwargs(
    id: int,
    *,
    body: BuildImagesRequestRequest | Unset = UNSET,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/clusterings/{id}/build-images/".format(
            id=quote(str(id), safe=""),
        ),
    }

    if not isinstance(body, Unset):
        _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Job | None:
    if response.status_code == 202:
        response_202 = Job.from_dict(response.json())

        return response_202

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[Job]:
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
    body: BuildImagesRequestRequest | Unset = UNSET,
) -> Response[Job]:
    """Start a job that builds this clustering's images by inheritance with buildah (Debian packages, on
    the
    worker's machine) and measures their layers next to the planner's prediction (Table 4.16 from
    images).

    Args:
        id (int):
        body (BuildImagesRequestRequest | Unset): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Job]
    """

    kwargs = _get_kwargs(
        id=id,
        body=body,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    id: int,
    *,
    client: AuthenticatedClient,
    body: BuildImagesRequestRequest | Unset = UNSET,
) -> Job | None:
    """Start a job that builds this clustering's images by inheritance with buildah (Debian packages, on
    the
    worker's machine) and measures their layers next to the planner's prediction (Table 4.16 from
    images).

    Args:
        id (int):
        body (BuildImagesRequestRequest | Unset): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Job
    """

    return sync_detailed(
        id=id,
        client=client,
        body=body,
    ).parsed


async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
    body: BuildImagesRequestRequest | Unset = UNSET,
) -> Response[Job]:
    """Start a job that builds this clustering's images by inheritance with buildah (Debian packages, on
    the
    worker's machine) and measures their layers next to the planner's prediction (Table 4.16 from
    images).

    Args:
        id (int):
        body (BuildImagesRequestRequest | Unset): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Job]
    """

    kwargs = _get_kwargs(
        id=id,
        body=body,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
    body: BuildImagesRequestRequest | Unset = UNSET,
) -> Job | None:
    """Start a job that builds this clustering's images by inheritance with buildah (Debian packages, on
    the
    worker's machine) and measures their layers next to the planner's prediction (Table 4.16 from
    images).

    Args:
        id (int):
        body (BuildImagesRequestRequest | Unset): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Job
    """

    return (
        await asyncio_detailed(
            id=id,
            client=client,
            body=body,
        )
    ).parsed
