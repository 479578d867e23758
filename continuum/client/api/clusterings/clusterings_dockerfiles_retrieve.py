from http import HTTPStatus
from io import BytesIO
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.clusterings_dockerfiles_retrieve_archive import (
    ClusteringsDockerfilesRetrieveArchive,
)
from ...types import UNSET, File, Response, Unset


def _get_kwargs(
    id: int,
    *,
    archive: ClusteringsDockerfilesRetrieveArchive | Unset = "tar.gz",
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    json_archive: str | Unset = UNSET
    if not isinstance(archive, Unset):
        json_archive = archive

    params["archive"] = json_archive

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/clusterings/{id}/dockerfiles/".format(
            id=quote(str(id), safe=""),
        ),
        "params": params,
    }

    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> File | None:
    if response.status_code == 200:
        response_200 = File(payload=BytesIO(response.content))

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[File]:
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
    archive: ClusteringsDockerfilesRetrieveArchive | Unset = "tar.gz",
) -> Response[File]:
    """The Dockerfiles (one directory per image), ``build.sh`` and ``plan.json`` as tar.gz or zip.

    Args:
        id (int):
        archive (ClusteringsDockerfilesRetrieveArchive | Unset):  Default: 'tar.gz'.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[File]
    """

    kwargs = _get_kwargs(
        id=id,
        archive=archive,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    id: int,
    *,
    client: AuthenticatedClient,
    archive: ClusteringsDockerfilesRetrieveArchive | Unset = "tar.gz",
) -> File | None:
    """The Dockerfiles (one directory per image), ``build.sh`` and ``plan.json`` as tar.gz or zip.

    Args:
        id (int):
        archive (ClusteringsDockerfilesRetrieveArchive | Unset):  Default: 'tar.gz'.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        File
    """

    return sync_detailed(
        id=id,
        client=client,
        archive=archive,
    ).parsed


async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
    archive: ClusteringsDockerfilesRetrieveArchive | Unset = "tar.gz",
) -> Response[File]:
    """The Dockerfiles (one directory per image), ``build.sh`` and ``plan.json`` as tar.gz or zip.

    Args:
        id (int):
        archive (ClusteringsDockerfilesRetrieveArchive | Unset):  Default: 'tar.gz'.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[File]
    """

    kwargs = _get_kwargs(
        id=id,
        archive=archive,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
    archive: ClusteringsDockerfilesRetrieveArchive | Unset = "tar.gz",
) -> File | None:
    """The Dockerfiles (one directory per image), ``build.sh`` and ``plan.json`` as tar.gz or zip.

    Args:
        id (int):
        archive (ClusteringsDockerfilesRetrieveArchive | Unset):  Default: 'tar.gz'.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        File
    """

    return (
        await asyncio_detailed(
            id=id,
            client=client,
            archive=archive,
        )
    ).parsed
