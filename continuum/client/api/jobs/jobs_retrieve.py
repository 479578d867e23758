from http import HTTPStatus
from typing import Any
from urllib.parse import quote
from uuid import UUID

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.job_detail import JobDetail
from ...types import Response


def _get_kwargs(
    id: UUID,
) -> dict[str, Any]:

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/jobs/{id}/".format(
            id=quote(str(id), safe=""),
        ),
    }

    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> JobDetail | None:
    if response.status_code == 200:
        response_200 = JobDetail.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[JobDetail]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    id: UUID,
    *,
    client: AuthenticatedClient,
) -> Response[JobDetail]:
    """Every long operation with its state and progress (0-100 and a message); one job also with its log.

    A running job whose worker is gone is queued again (or failed) before it is shown, so a reader never
    waits on a run that cannot end (apps/jobs/liveness.py). ``POST {id}/cancel/`` stops a job (a queued
    one at
    once, a running one at its next step); ``POST {id}/retry/`` runs a failed or cancelled job again as
    a new
    job with the same arguments.

    Args:
        id (UUID):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[JobDetail]
    """

    kwargs = _get_kwargs(
        id=id,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    id: UUID,
    *,
    client: AuthenticatedClient,
) -> JobDetail | None:
    """Every long operation with its state and progress (0-100 and a message); one job also with its log.

    A running job whose worker is gone is queued again (or failed) before it is shown, so a reader never
    waits on a run that cannot end (apps/jobs/liveness.py). ``POST {id}/cancel/`` stops a job (a queued
    one at
    once, a running one at its next step); ``POST {id}/retry/`` runs a failed or cancelled job again as
    a new
    job with the same arguments.

    Args:
        id (UUID):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        JobDetail
    """

    return sync_detailed(
        id=id,
        client=client,
    ).parsed


async def asyncio_detailed(
    id: UUID,
    *,
    client: AuthenticatedClient,
) -> Response[JobDetail]:
    """Every long operation with its state and progress (0-100 and a message); one job also with its log.

    A running job whose worker is gone is queued again (or failed) before it is shown, so a reader never
    waits on a run that cannot end (apps/jobs/liveness.py). ``POST {id}/cancel/`` stops a job (a queued
    one at
    once, a running one at its next step); ``POST {id}/retry/`` runs a failed or cancelled job again as
    a new
    job with the same arguments.

    Args:
        id (UUID):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[JobDetail]
    """

    kwargs = _get_kwargs(
        id=id,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    id: UUID,
    *,
    client: AuthenticatedClient,
) -> JobDetail | None:
    """Every long operation with its state and progress (0-100 and a message); one job also with its log.

    A running job whose worker is gone is queued again (or failed) before it is shown, so a reader never
    waits on a run that cannot end (apps/jobs/liveness.py). ``POST {id}/cancel/`` stops a job (a queued
    one at
    once, a running one at its next step); ``POST {id}/retry/`` runs a failed or cancelled job again as
    a new
    job with the same arguments.

    Args:
        id (UUID):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        JobDetail
    """

    return (
        await asyncio_detailed(
            id=id,
            client=client,
        )
    ).parsed
