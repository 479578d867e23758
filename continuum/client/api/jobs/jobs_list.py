from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.jobs_list_state import JobsListState
from ...models.paginated_job_list import PaginatedJobList
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    fleet_slug: str | Unset = UNSET,
    kind: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    state: JobsListState | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["fleet__slug"] = fleet_slug

    params["kind"] = kind

    params["limit"] = limit

    params["offset"] = offset

    params["ordering"] = ordering

    params["search"] = search

    json_state: str | Unset = UNSET
    if not isinstance(state, Unset):
        json_state = state

    params["state"] = json_state

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/jobs/",
        "params": params,
    }

    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> PaginatedJobList | None:
    if response.status_code == 200:
        response_200 = PaginatedJobList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[PaginatedJobList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    fleet_slug: str | Unset = UNSET,
    kind: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    state: JobsListState | Unset = UNSET,
) -> Response[PaginatedJobList]:
    """Every long operation with its state and progress (0-100 and a message); one job also with its log.

    A running job whose worker is gone is queued again (or failed) before it is shown, so a reader never
    waits on a run that cannot end (apps/jobs/liveness.py). ``POST {id}/cancel/`` stops a job (a queued
    one at
    once, a running one at its next step); ``POST {id}/retry/`` runs a failed or cancelled job again as
    a new
    job with the same arguments.

    Args:
        fleet_slug (str | Unset):
        kind (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        state (JobsListState | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedJobList]
    """

    kwargs = _get_kwargs(
        fleet_slug=fleet_slug,
        kind=kind,
        limit=limit,
        offset=offset,
        ordering=ordering,
        search=search,
        state=state,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    fleet_slug: str | Unset = UNSET,
    kind: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    state: JobsListState | Unset = UNSET,
) -> PaginatedJobList | None:
    """Every long operation with its state and progress (0-100 and a message); one job also with its log.

    A running job whose worker is gone is queued again (or failed) before it is shown, so a reader never
    waits on a run that cannot end (apps/jobs/liveness.py). ``POST {id}/cancel/`` stops a job (a queued
    one at
    once, a running one at its next step); ``POST {id}/retry/`` runs a failed or cancelled job again as
    a new
    job with the same arguments.

    Args:
        fleet_slug (str | Unset):
        kind (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        state (JobsListState | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedJobList
    """

    return sync_detailed(
        client=client,
        fleet_slug=fleet_slug,
        kind=kind,
        limit=limit,
        offset=offset,
        ordering=ordering,
        search=search,
        state=state,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    fleet_slug: str | Unset = UNSET,
    kind: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    state: JobsListState | Unset = UNSET,
) -> Response[PaginatedJobList]:
    """Every long operation with its state and progress (0-100 and a message); one job also with its log.

    A running job whose worker is gone is queued again (or failed) before it is shown, so a reader never
    waits on a run that cannot end (apps/jobs/liveness.py). ``POST {id}/cancel/`` stops a job (a queued
    one at
    once, a running one at its next step); ``POST {id}/retry/`` runs a failed or cancelled job again as
    a new
    job with the same arguments.

    Args:
        fleet_slug (str | Unset):
        kind (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        state (JobsListState | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedJobList]
    """

    kwargs = _get_kwargs(
        fleet_slug=fleet_slug,
        kind=kind,
        limit=limit,
        offset=offset,
        ordering=ordering,
        search=search,
        state=state,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    fleet_slug: str | Unset = UNSET,
    kind: str | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    search: str | Unset = UNSET,
    state: JobsListState | Unset = UNSET,
) -> PaginatedJobList | None:
    """Every long operation with its state and progress (0-100 and a message); one job also with its log.

    A running job whose worker is gone is queued again (or failed) before it is shown, so a reader never
    waits on a run that cannot end (apps/jobs/liveness.py). ``POST {id}/cancel/`` stops a job (a queued
    one at
    once, a running one at its next step); ``POST {id}/retry/`` runs a failed or cancelled job again as
    a new
    job with the same arguments.

    Args:
        fleet_slug (str | Unset):
        kind (str | Unset):
        limit (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        search (str | Unset):
        state (JobsListState | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedJobList
    """

    return (
        await asyncio_detailed(
            client=client,
            fleet_slug=fleet_slug,
            kind=kind,
            limit=limit,
            offset=offset,
            ordering=ordering,
            search=search,
            state=state,
        )
    ).parsed
