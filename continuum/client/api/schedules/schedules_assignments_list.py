from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_assignment_list import PaginatedAssignmentList
from ...models.schedules_assignments_list_placement import (
    SchedulesAssignmentsListPlacement,
)
from ...types import UNSET, Response, Unset


def _get_kwargs(
    id: int,
    *,
    cursor: str | Unset = UNSET,
    frame: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    placement: SchedulesAssignmentsListPlacement | Unset = UNSET,
    processor: str | Unset = UNSET,
    task: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["cursor"] = cursor

    params["frame"] = frame

    params["limit"] = limit

    params["offset"] = offset

    json_placement: str | Unset = UNSET
    if not isinstance(placement, Unset):
        json_placement = placement

    params["placement"] = json_placement

    params["processor"] = processor

    params["task"] = task

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/schedules/{id}/assignments/".format(
            id=quote(str(id), safe=""),
        ),
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedAssignmentList | None:
    if response.status_code == 200:
        response_200 = PaginatedAssignmentList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedAssignmentList]:
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
    cursor: str | Unset = UNSET,
    frame: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    placement: SchedulesAssignmentsListPlacement | Unset = UNSET,
    processor: str | Unset = UNSET,
    task: str | Unset = UNSET,
) -> Response[PaginatedAssignmentList]:
    """The schedule's assignments, paginated (``limit``, ``offset``) in start order, filtered by part of
    the
    task's id (``task``), the processor (``processor``), the frame (``frame``) or the placement status
    (``placement``); a malformed filter or a processor not in the schedule is a 400 naming it.

    Args:
        id (int):
        cursor (str | Unset):
        frame (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        placement (SchedulesAssignmentsListPlacement | Unset):
        processor (str | Unset):
        task (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedAssignmentList]
    """

    kwargs = _get_kwargs(
        id=id,
        cursor=cursor,
        frame=frame,
        limit=limit,
        offset=offset,
        placement=placement,
        processor=processor,
        task=task,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    id: int,
    *,
    client: AuthenticatedClient,
    cursor: str | Unset = UNSET,
    frame: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    placement: SchedulesAssignmentsListPlacement | Unset = UNSET,
    processor: str | Unset = UNSET,
    task: str | Unset = UNSET,
) -> PaginatedAssignmentList | None:
    """The schedule's assignments, paginated (``limit``, ``offset``) in start order, filtered by part of
    the
    task's id (``task``), the processor (``processor``), the frame (``frame``) or the placement status
    (``placement``); a malformed filter or a processor not in the schedule is a 400 naming it.

    Args:
        id (int):
        cursor (str | Unset):
        frame (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        placement (SchedulesAssignmentsListPlacement | Unset):
        processor (str | Unset):
        task (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedAssignmentList
    """

    return sync_detailed(
        id=id,
        client=client,
        cursor=cursor,
        frame=frame,
        limit=limit,
        offset=offset,
        placement=placement,
        processor=processor,
        task=task,
    ).parsed


async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
    cursor: str | Unset = UNSET,
    frame: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    placement: SchedulesAssignmentsListPlacement | Unset = UNSET,
    processor: str | Unset = UNSET,
    task: str | Unset = UNSET,
) -> Response[PaginatedAssignmentList]:
    """The schedule's assignments, paginated (``limit``, ``offset``) in start order, filtered by part of
    the
    task's id (``task``), the processor (``processor``), the frame (``frame``) or the placement status
    (``placement``); a malformed filter or a processor not in the schedule is a 400 naming it.

    Args:
        id (int):
        cursor (str | Unset):
        frame (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        placement (SchedulesAssignmentsListPlacement | Unset):
        processor (str | Unset):
        task (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedAssignmentList]
    """

    kwargs = _get_kwargs(
        id=id,
        cursor=cursor,
        frame=frame,
        limit=limit,
        offset=offset,
        placement=placement,
        processor=processor,
        task=task,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
    cursor: str | Unset = UNSET,
    frame: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    offset: int | Unset = UNSET,
    placement: SchedulesAssignmentsListPlacement | Unset = UNSET,
    processor: str | Unset = UNSET,
    task: str | Unset = UNSET,
) -> PaginatedAssignmentList | None:
    """The schedule's assignments, paginated (``limit``, ``offset``) in start order, filtered by part of
    the
    task's id (``task``), the processor (``processor``), the frame (``frame``) or the placement status
    (``placement``); a malformed filter or a processor not in the schedule is a 400 naming it.

    Args:
        id (int):
        cursor (str | Unset):
        frame (int | Unset):
        limit (int | Unset):
        offset (int | Unset):
        placement (SchedulesAssignmentsListPlacement | Unset):
        processor (str | Unset):
        task (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedAssignmentList
    """

    return (
        await asyncio_detailed(
            id=id,
            client=client,
            cursor=cursor,
            frame=frame,
            limit=limit,
            offset=offset,
            placement=placement,
            processor=processor,
            task=task,
        )
    ).parsed
