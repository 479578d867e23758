from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.compare_request_request import CompareRequestRequest
from ...models.job import Job
from ...types import UNSET, Response, Unset


def _get_kwargs(
    id: int,
    *,
    body: CompareRequestRequest | Unset = UNSET,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/applications/{id}/compare/".format(
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
    body: CompareRequestRequest | Unset = UNSET,
) -> Response[Job]:
    """Start a job that runs several algorithms on this application and target (frames optional) and stores
    each schedule plus a comparison (makespan, SLR, speedup vs VisionWorks, overlap, idle time).

    Args:
        id (int):
        body (CompareRequestRequest | Unset): Run several algorithms on one application and target
            and compare them (thesis Tables 4.1, 4.3).

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
    body: CompareRequestRequest | Unset = UNSET,
) -> Job | None:
    """Start a job that runs several algorithms on this application and target (frames optional) and stores
    each schedule plus a comparison (makespan, SLR, speedup vs VisionWorks, overlap, idle time).

    Args:
        id (int):
        body (CompareRequestRequest | Unset): Run several algorithms on one application and target
            and compare them (thesis Tables 4.1, 4.3).

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
    body: CompareRequestRequest | Unset = UNSET,
) -> Response[Job]:
    """Start a job that runs several algorithms on this application and target (frames optional) and stores
    each schedule plus a comparison (makespan, SLR, speedup vs VisionWorks, overlap, idle time).

    Args:
        id (int):
        body (CompareRequestRequest | Unset): Run several algorithms on one application and target
            and compare them (thesis Tables 4.1, 4.3).

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
    body: CompareRequestRequest | Unset = UNSET,
) -> Job | None:
    """Start a job that runs several algorithms on this application and target (frames optional) and stores
    each schedule plus a comparison (makespan, SLR, speedup vs VisionWorks, overlap, idle time).

    Args:
        id (int):
        body (CompareRequestRequest | Unset): Run several algorithms on one application and target
            and compare them (thesis Tables 4.1, 4.3).

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
