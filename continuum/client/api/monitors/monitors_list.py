from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.monitors_list_verdict import MonitorsListVerdict
from ...models.paginated_monitor_list import PaginatedMonitorList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    assertion: int | Unset = UNSET,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    node: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    tolerant: bool | Unset = UNSET,
    verdict: MonitorsListVerdict | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["assertion"] = assertion

    params["cluster"] = cluster

    params["limit"] = limit

    params["node"] = node

    params["offset"] = offset

    params["ordering"] = ordering

    params["search"] = search

    params["tolerant"] = tolerant

    json_verdict: str | Unset = UNSET
    if not isinstance(verdict, Unset):
        json_verdict = verdict

    params["verdict"] = json_verdict

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/monitors/",
        "params": params,
    }

    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> PaginatedMonitorList | None:
    if response.status_code == 200:
        response_200 = PaginatedMonitorList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedMonitorList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    assertion: int | Unset = UNSET,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    node: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    tolerant: bool | Unset = UNSET,
    verdict: MonitorsListVerdict | Unset = UNSET,
) -> Response[PaginatedMonitorList]:
    """Monitors of assertions on a cluster; ``node`` is the node whose handler runs it.

    Args:
        assertion (int | Unset):
        cluster (int | Unset):
        limit (int | Unset):
        node (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        tolerant (bool | Unset):
        verdict (MonitorsListVerdict | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedMonitorList]
    """

    kwargs = _get_kwargs(
        assertion=assertion,
        cluster=cluster,
        limit=limit,
        node=node,
        offset=offset,
        ordering=ordering,
        search=search,
        tolerant=tolerant,
        verdict=verdict,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    assertion: int | Unset = UNSET,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    node: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    tolerant: bool | Unset = UNSET,
    verdict: MonitorsListVerdict | Unset = UNSET,
) -> PaginatedMonitorList | None:
    """Monitors of assertions on a cluster; ``node`` is the node whose handler runs it.

    Args:
        assertion (int | Unset):
        cluster (int | Unset):
        limit (int | Unset):
        node (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        tolerant (bool | Unset):
        verdict (MonitorsListVerdict | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedMonitorList
    """

    return sync_detailed(
        client=client,
        assertion=assertion,
        cluster=cluster,
        limit=limit,
        node=node,
        offset=offset,
        ordering=ordering,
        search=search,
        tolerant=tolerant,
        verdict=verdict,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    assertion: int | Unset = UNSET,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    node: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    tolerant: bool | Unset = UNSET,
    verdict: MonitorsListVerdict | Unset = UNSET,
) -> Response[PaginatedMonitorList]:
    """Monitors of assertions on a cluster; ``node`` is the node whose handler runs it.

    Args:
        assertion (int | Unset):
        cluster (int | Unset):
        limit (int | Unset):
        node (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        tolerant (bool | Unset):
        verdict (MonitorsListVerdict | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedMonitorList]
    """

    kwargs = _get_kwargs(
        assertion=assertion,
        cluster=cluster,
        limit=limit,
        node=node,
        offset=offset,
        ordering=ordering,
        search=search,
        tolerant=tolerant,
        verdict=verdict,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    assertion: int | Unset = UNSET,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    node: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    tolerant: bool | Unset = UNSET,
    verdict: MonitorsListVerdict | Unset = UNSET,
) -> PaginatedMonitorList | None:
    """Monitors of assertions on a cluster; ``node`` is the node whose handler runs it.

    Args:
        assertion (int | Unset):
        cluster (int | Unset):
        limit (int | Unset):
        node (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        tolerant (bool | Unset):
        verdict (MonitorsListVerdict | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedMonitorList
    """

    return (
        await asyncio_detailed(
            client=client,
            assertion=assertion,
            cluster=cluster,
            limit=limit,
            node=node,
            offset=offset,
            ordering=ordering,
            search=search,
            tolerant=tolerant,
            verdict=verdict,
        )
    ).parsed
