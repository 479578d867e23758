from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_real_time_list import PaginatedRealTimeList
from ...models.realtimes_list_criticality import RealtimesListCriticality
from ...models.realtimes_list_sync_state import RealtimesListSyncState
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    cluster: int | Unset = UNSET,
    criticality: RealtimesListCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    sync_state: RealtimesListSyncState | Unset = UNSET,
) -> dict[str, Any]:

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
        "method": "get",
        "url": "/api/v1/realtimes/",
        "params": params,
    }

    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> PaginatedRealTimeList | None:
    if response.status_code == 200:
        response_200 = PaginatedRealTimeList.from_dict(response.json())

        return response_200

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
    cluster: int | Unset = UNSET,
    criticality: RealtimesListCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    sync_state: RealtimesListSyncState | Unset = UNSET,
) -> Response[PaginatedRealTimeList]:
    """RealTime objects (Listing 3.33). Saving one writes it to the cluster's Kubernetes API as well.

    Args:
        cluster (int | Unset):
        criticality (RealtimesListCriticality | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        sync_state (RealtimesListSyncState | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedRealTimeList]
    """

    kwargs = _get_kwargs(
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
    cluster: int | Unset = UNSET,
    criticality: RealtimesListCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    sync_state: RealtimesListSyncState | Unset = UNSET,
) -> PaginatedRealTimeList | None:
    """RealTime objects (Listing 3.33). Saving one writes it to the cluster's Kubernetes API as well.

    Args:
        cluster (int | Unset):
        criticality (RealtimesListCriticality | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        sync_state (RealtimesListSyncState | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedRealTimeList
    """

    return sync_detailed(
        client=client,
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
    cluster: int | Unset = UNSET,
    criticality: RealtimesListCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    sync_state: RealtimesListSyncState | Unset = UNSET,
) -> Response[PaginatedRealTimeList]:
    """RealTime objects (Listing 3.33). Saving one writes it to the cluster's Kubernetes API as well.

    Args:
        cluster (int | Unset):
        criticality (RealtimesListCriticality | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        sync_state (RealtimesListSyncState | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedRealTimeList]
    """

    kwargs = _get_kwargs(
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
    cluster: int | Unset = UNSET,
    criticality: RealtimesListCriticality | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    sync_state: RealtimesListSyncState | Unset = UNSET,
) -> PaginatedRealTimeList | None:
    """RealTime objects (Listing 3.33). Saving one writes it to the cluster's Kubernetes API as well.

    Args:
        cluster (int | Unset):
        criticality (RealtimesListCriticality | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        sync_state (RealtimesListSyncState | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedRealTimeList
    """

    return (
        await asyncio_detailed(
            client=client,
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
