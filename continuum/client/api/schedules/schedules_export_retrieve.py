from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.schedules_export_retrieve_as import SchedulesExportRetrieveAs
from ...types import UNSET, Response, Unset


def _get_kwargs(
    id: int,
    *,
    as_: SchedulesExportRetrieveAs | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    json_as_: str | Unset = UNSET
    if not isinstance(as_, Unset):
        json_as_ = as_

    params["as"] = json_as_

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/schedules/{id}/export/".format(
            id=quote(str(id), safe=""),
        ),
        "params": params,
    }

    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> str | None:
    if response.status_code == 200:
        response_200 = response.text
        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[str]:
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
    as_: SchedulesExportRetrieveAs | Unset = UNSET,
) -> Response[str]:
    """Every assignment of the schedule in one streamed answer, in start order: CSV with a header
    (``as=csv``, the default) or one JSON object a line (``as=jsonl``).

    Args:
        id (int):
        as_ (SchedulesExportRetrieveAs | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[str]
    """

    kwargs = _get_kwargs(
        id=id,
        as_=as_,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    id: int,
    *,
    client: AuthenticatedClient,
    as_: SchedulesExportRetrieveAs | Unset = UNSET,
) -> str | None:
    """Every assignment of the schedule in one streamed answer, in start order: CSV with a header
    (``as=csv``, the default) or one JSON object a line (``as=jsonl``).

    Args:
        id (int):
        as_ (SchedulesExportRetrieveAs | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        str
    """

    return sync_detailed(
        id=id,
        client=client,
        as_=as_,
    ).parsed


async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
    as_: SchedulesExportRetrieveAs | Unset = UNSET,
) -> Response[str]:
    """Every assignment of the schedule in one streamed answer, in start order: CSV with a header
    (``as=csv``, the default) or one JSON object a line (``as=jsonl``).

    Args:
        id (int):
        as_ (SchedulesExportRetrieveAs | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[str]
    """

    kwargs = _get_kwargs(
        id=id,
        as_=as_,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
    as_: SchedulesExportRetrieveAs | Unset = UNSET,
) -> str | None:
    """Every assignment of the schedule in one streamed answer, in start order: CSV with a header
    (``as=csv``, the default) or one JSON object a line (``as=jsonl``).

    Args:
        id (int):
        as_ (SchedulesExportRetrieveAs | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        str
    """

    return (
        await asyncio_detailed(
            id=id,
            client=client,
            as_=as_,
        )
    ).parsed
