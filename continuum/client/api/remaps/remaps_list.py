from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_remap_event_list import PaginatedRemapEventList
from ...models.remaps_list_decision import RemapsListDecision
from ...models.remaps_list_status import RemapsListStatus
from ...models.remaps_list_trigger import RemapsListTrigger
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    application: int | Unset = UNSET,
    decision: RemapsListDecision | Unset = UNSET,
    limit: int | Unset = UNSET,
    new_schedule: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    schedule: int | Unset = UNSET,
    search: str | Unset = UNSET,
    status: RemapsListStatus | Unset = UNSET,
    trigger: RemapsListTrigger | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["application"] = application

    json_decision: str | Unset = UNSET
    if not isinstance(decision, Unset):
        json_decision = decision

    params["decision"] = json_decision

    params["limit"] = limit

    params["new_schedule"] = new_schedule

    params["offset"] = offset

    params["ordering"] = ordering

    params["schedule"] = schedule

    params["search"] = search

    json_status: str | Unset = UNSET
    if not isinstance(status, Unset):
        json_status = status

    params["status"] = json_status

    json_trigger: str | Unset = UNSET
    if not isinstance(trigger, Unset):
        json_trigger = trigger

    params["trigger"] = json_trigger

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/remaps/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedRemapEventList | None:
    if response.status_code == 200:
        response_200 = PaginatedRemapEventList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedRemapEventList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    application: int | Unset = UNSET,
    decision: RemapsListDecision | Unset = UNSET,
    limit: int | Unset = UNSET,
    new_schedule: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    schedule: int | Unset = UNSET,
    search: str | Unset = UNSET,
    status: RemapsListStatus | Unset = UNSET,
    trigger: RemapsListTrigger | Unset = UNSET,
) -> Response[PaginatedRemapEventList]:
    """Every remap of a schedule: what Algorithm 2 decided, what moved, what changed in Kubernetes.

    Args:
        application (int | Unset):
        decision (RemapsListDecision | Unset):
        limit (int | Unset):
        new_schedule (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        schedule (int | Unset):
        search (str | Unset):
        status (RemapsListStatus | Unset):
        trigger (RemapsListTrigger | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedRemapEventList]
    """

    kwargs = _get_kwargs(
        application=application,
        decision=decision,
        limit=limit,
        new_schedule=new_schedule,
        offset=offset,
        ordering=ordering,
        schedule=schedule,
        search=search,
        status=status,
        trigger=trigger,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    application: int | Unset = UNSET,
    decision: RemapsListDecision | Unset = UNSET,
    limit: int | Unset = UNSET,
    new_schedule: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    schedule: int | Unset = UNSET,
    search: str | Unset = UNSET,
    status: RemapsListStatus | Unset = UNSET,
    trigger: RemapsListTrigger | Unset = UNSET,
) -> PaginatedRemapEventList | None:
    """Every remap of a schedule: what Algorithm 2 decided, what moved, what changed in Kubernetes.

    Args:
        application (int | Unset):
        decision (RemapsListDecision | Unset):
        limit (int | Unset):
        new_schedule (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        schedule (int | Unset):
        search (str | Unset):
        status (RemapsListStatus | Unset):
        trigger (RemapsListTrigger | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedRemapEventList
    """

    return sync_detailed(
        client=client,
        application=application,
        decision=decision,
        limit=limit,
        new_schedule=new_schedule,
        offset=offset,
        ordering=ordering,
        schedule=schedule,
        search=search,
        status=status,
        trigger=trigger,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    application: int | Unset = UNSET,
    decision: RemapsListDecision | Unset = UNSET,
    limit: int | Unset = UNSET,
    new_schedule: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    schedule: int | Unset = UNSET,
    search: str | Unset = UNSET,
    status: RemapsListStatus | Unset = UNSET,
    trigger: RemapsListTrigger | Unset = UNSET,
) -> Response[PaginatedRemapEventList]:
    """Every remap of a schedule: what Algorithm 2 decided, what moved, what changed in Kubernetes.

    Args:
        application (int | Unset):
        decision (RemapsListDecision | Unset):
        limit (int | Unset):
        new_schedule (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        schedule (int | Unset):
        search (str | Unset):
        status (RemapsListStatus | Unset):
        trigger (RemapsListTrigger | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedRemapEventList]
    """

    kwargs = _get_kwargs(
        application=application,
        decision=decision,
        limit=limit,
        new_schedule=new_schedule,
        offset=offset,
        ordering=ordering,
        schedule=schedule,
        search=search,
        status=status,
        trigger=trigger,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    application: int | Unset = UNSET,
    decision: RemapsListDecision | Unset = UNSET,
    limit: int | Unset = UNSET,
    new_schedule: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    schedule: int | Unset = UNSET,
    search: str | Unset = UNSET,
    status: RemapsListStatus | Unset = UNSET,
    trigger: RemapsListTrigger | Unset = UNSET,
) -> PaginatedRemapEventList | None:
    """Every remap of a schedule: what Algorithm 2 decided, what moved, what changed in Kubernetes.

    Args:
        application (int | Unset):
        decision (RemapsListDecision | Unset):
        limit (int | Unset):
        new_schedule (int | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        schedule (int | Unset):
        search (str | Unset):
        status (RemapsListStatus | Unset):
        trigger (RemapsListTrigger | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedRemapEventList
    """

    return (
        await asyncio_detailed(
            client=client,
            application=application,
            decision=decision,
            limit=limit,
            new_schedule=new_schedule,
            offset=offset,
            ordering=ordering,
            schedule=schedule,
            search=search,
            status=status,
            trigger=trigger,
        )
    ).parsed
