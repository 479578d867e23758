from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_monitor_verdict_list import PaginatedMonitorVerdictList
from ...models.verdicts_list_verdict import VerdictsListVerdict
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    verdict: VerdictsListVerdict | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["limit"] = limit

    params["monitor"] = monitor

    params["offset"] = offset

    params["ordering"] = ordering

    params["search"] = search

    json_verdict: str | Unset = UNSET
    if not isinstance(verdict, Unset):
        json_verdict = verdict

    params["verdict"] = json_verdict

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/verdicts/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedMonitorVerdictList | None:
    if response.status_code == 200:
        response_200 = PaginatedMonitorVerdictList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedMonitorVerdictList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    verdict: VerdictsListVerdict | Unset = UNSET,
) -> Response[PaginatedMonitorVerdictList]:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        limit (int | Unset):
        monitor (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        verdict (VerdictsListVerdict | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedMonitorVerdictList]
    """

    kwargs = _get_kwargs(
        limit=limit,
        monitor=monitor,
        offset=offset,
        ordering=ordering,
        search=search,
        verdict=verdict,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    verdict: VerdictsListVerdict | Unset = UNSET,
) -> PaginatedMonitorVerdictList | None:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        limit (int | Unset):
        monitor (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        verdict (VerdictsListVerdict | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedMonitorVerdictList
    """

    return sync_detailed(
        client=client,
        limit=limit,
        monitor=monitor,
        offset=offset,
        ordering=ordering,
        search=search,
        verdict=verdict,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    verdict: VerdictsListVerdict | Unset = UNSET,
) -> Response[PaginatedMonitorVerdictList]:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        limit (int | Unset):
        monitor (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        verdict (VerdictsListVerdict | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedMonitorVerdictList]
    """

    kwargs = _get_kwargs(
        limit=limit,
        monitor=monitor,
        offset=offset,
        ordering=ordering,
        search=search,
        verdict=verdict,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    limit: int | Unset = UNSET,
    monitor: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    verdict: VerdictsListVerdict | Unset = UNSET,
) -> PaginatedMonitorVerdictList | None:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404.

    Args:
        limit (int | Unset):
        monitor (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        verdict (VerdictsListVerdict | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedMonitorVerdictList
    """

    return (
        await asyncio_detailed(
            client=client,
            limit=limit,
            monitor=monitor,
            offset=offset,
            ordering=ordering,
            search=search,
            verdict=verdict,
        )
    ).parsed
