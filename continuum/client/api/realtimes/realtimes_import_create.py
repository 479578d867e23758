from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_real_time_list import PaginatedRealTimeList
from ...models.real_time_import_request import RealTimeImportRequest
from ...models.realtimes_import_create_criticality import (
    RealtimesImportCreateCriticality,
)
from ...models.realtimes_import_create_sync_state import (
    RealtimesImportCreateSyncState,
)
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    body: RealTimeImportRequest,
    cluster: int | Unset = UNSET,
    criticality: RealtimesImportCreateCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    sync_state: RealtimesImportCreateSyncState | Unset = UNSET,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    params: dict[str, Any] = {}

    params["cluster"] = cluster

    json_criticality: str | Unset = UNSET
    if not isinstance(criticality, Unset):
        json_criticality = criticality

    params["criticality"] = json_criticality

    params["limit"] = limit

    params["namespace"] = namespace

    params["offset"] = offset

    params["ordering"] = ordering

    params["search"] = search

    json_sync_state: str | Unset = UNSET
    if not isinstance(sync_state, Unset):
        json_sync_state = sync_state

    params["sync_state"] = json_sync_state

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/realtimes/import/",
        "params": params,
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> PaginatedRealTimeList | None:
    if response.status_code == 201:
        response_201 = PaginatedRealTimeList.from_dict(response.json())

        return response_201

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedRealTimeList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: RealTimeImportRequest,
    cluster: int | Unset = UNSET,
    criticality: RealtimesImportCreateCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    sync_state: RealtimesImportCreateSyncState | Unset = UNSET,
) -> Response[PaginatedRealTimeList]:
    """Create (or replace) RealTime objects from YAML; all or nothing.

    Args:
        cluster (int | Unset):
        criticality (RealtimesImportCreateCriticality | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        sync_state (RealtimesImportCreateSyncState | Unset):
        body (RealTimeImportRequest): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedRealTimeList]
    """

    kwargs = _get_kwargs(
        body=body,
        cluster=cluster,
        criticality=criticality,
        limit=limit,
        namespace=namespace,
        offset=offset,
        ordering=ordering,
        search=search,
        sync_state=sync_state,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    body: RealTimeImportRequest,
    cluster: int | Unset = UNSET,
    criticality: RealtimesImportCreateCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    sync_state: RealtimesImportCreateSyncState | Unset = UNSET,
) -> PaginatedRealTimeList | None:
    """Create (or replace) RealTime objects from YAML; all or nothing.

    Args:
        cluster (int | Unset):
        criticality (RealtimesImportCreateCriticality | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        sync_state (RealtimesImportCreateSyncState | Unset):
        body (RealTimeImportRequest): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedRealTimeList
    """

    return sync_detailed(
        client=client,
        body=body,
        cluster=cluster,
        criticality=criticality,
        limit=limit,
        namespace=namespace,
        offset=offset,
        ordering=ordering,
        search=search,
        sync_state=sync_state,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: RealTimeImportRequest,
    cluster: int | Unset = UNSET,
    criticality: RealtimesImportCreateCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    sync_state: RealtimesImportCreateSyncState | Unset = UNSET,
) -> Response[PaginatedRealTimeList]:
    """Create (or replace) RealTime objects from YAML; all or nothing.

    Args:
        cluster (int | Unset):
        criticality (RealtimesImportCreateCriticality | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        sync_state (RealtimesImportCreateSyncState | Unset):
        body (RealTimeImportRequest): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedRealTimeList]
    """

    kwargs = _get_kwargs(
        body=body,
        cluster=cluster,
        criticality=criticality,
        limit=limit,
        namespace=namespace,
        offset=offset,
        ordering=ordering,
        search=search,
        sync_state=sync_state,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    body: RealTimeImportRequest,
    cluster: int | Unset = UNSET,
    criticality: RealtimesImportCreateCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    sync_state: RealtimesImportCreateSyncState | Unset = UNSET,
) -> PaginatedRealTimeList | None:
    """Create (or replace) RealTime objects from YAML; all or nothing.

    Args:
        cluster (int | Unset):
        criticality (RealtimesImportCreateCriticality | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        sync_state (RealtimesImportCreateSyncState | Unset):
        body (RealTimeImportRequest): The base of every plain serializer of the API.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedRealTimeList
    """

    return (
        await asyncio_detailed(
            client=client,
            body=body,
            cluster=cluster,
            criticality=criticality,
            limit=limit,
            namespace=namespace,
            offset=offset,
            ordering=ordering,
            search=search,
            sync_state=sync_state,
        )
    ).parsed
