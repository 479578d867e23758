from http import HTTPStatus
from typing import Any
from urllib.parse import quote

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.patched_ros_graph_request import PatchedRosGraphRequest
from ...models.ros_graph import RosGraph
from ...types import UNSET, Response, Unset


def _get_kwargs(
    id: int,
    *,
    body: PatchedRosGraphRequest | Unset = UNSET,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "patch",
        "url": "/api/v1/rosgraphs/{id}/".format(
            id=quote(str(id), safe=""),
        ),
    }

    if not isinstance(body, Unset):
        _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> RosGraph | None:
    if response.status_code == 200:
        response_200 = RosGraph.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[RosGraph]:
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
    body: PatchedRosGraphRequest | Unset = UNSET,
) -> Response[RosGraph]:
    """ROS computation graphs. Create them with ``import``; PATCH edits levels, rates and message sizes.

    Args:
        id (int):
        body (PatchedRosGraphRequest | Unset): A ROS graph; PATCH edits levels, topic rates and
            message sizes, node profiles and package sizes.

            ``levels``: ``{ros node: level or null}``; ``topics``: ``{topic: {rate_hz | period_ms |
            publisher_rates_hz, msg_bytes, msg_type}}``; ``nodes``: ``{ros node: {level, context,
            origin, cpu,
            memory_mib, packages}}``; ``packages``: ``{package: size_mib | {size_mib, archs, apt} |
            null}``.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[RosGraph]
    """

    kwargs = _get_kwargs(
        id=id,
        body=body,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    id: int,
    *,
    client: AuthenticatedClient,
    body: PatchedRosGraphRequest | Unset = UNSET,
) -> RosGraph | None:
    """ROS computation graphs. Create them with ``import``; PATCH edits levels, rates and message sizes.

    Args:
        id (int):
        body (PatchedRosGraphRequest | Unset): A ROS graph; PATCH edits levels, topic rates and
            message sizes, node profiles and package sizes.

            ``levels``: ``{ros node: level or null}``; ``topics``: ``{topic: {rate_hz | period_ms |
            publisher_rates_hz, msg_bytes, msg_type}}``; ``nodes``: ``{ros node: {level, context,
            origin, cpu,
            memory_mib, packages}}``; ``packages``: ``{package: size_mib | {size_mib, archs, apt} |
            null}``.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        RosGraph
    """

    return sync_detailed(
        id=id,
        client=client,
        body=body,
    ).parsed


async def asyncio_detailed(
    id: int,
    *,
    client: AuthenticatedClient,
    body: PatchedRosGraphRequest | Unset = UNSET,
) -> Response[RosGraph]:
    """ROS computation graphs. Create them with ``import``; PATCH edits levels, rates and message sizes.

    Args:
        id (int):
        body (PatchedRosGraphRequest | Unset): A ROS graph; PATCH edits levels, topic rates and
            message sizes, node profiles and package sizes.

            ``levels``: ``{ros node: level or null}``; ``topics``: ``{topic: {rate_hz | period_ms |
            publisher_rates_hz, msg_bytes, msg_type}}``; ``nodes``: ``{ros node: {level, context,
            origin, cpu,
            memory_mib, packages}}``; ``packages``: ``{package: size_mib | {size_mib, archs, apt} |
            null}``.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[RosGraph]
    """

    kwargs = _get_kwargs(
        id=id,
        body=body,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    id: int,
    *,
    client: AuthenticatedClient,
    body: PatchedRosGraphRequest | Unset = UNSET,
) -> RosGraph | None:
    """ROS computation graphs. Create them with ``import``; PATCH edits levels, rates and message sizes.

    Args:
        id (int):
        body (PatchedRosGraphRequest | Unset): A ROS graph; PATCH edits levels, topic rates and
            message sizes, node profiles and package sizes.

            ``levels``: ``{ros node: level or null}``; ``topics``: ``{topic: {rate_hz | period_ms |
            publisher_rates_hz, msg_bytes, msg_type}}``; ``nodes``: ``{ros node: {level, context,
            origin, cpu,
            memory_mib, packages}}``; ``packages``: ``{package: size_mib | {size_mib, archs, apt} |
            null}``.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        RosGraph
    """

    return (
        await asyncio_detailed(
            id=id,
            client=client,
            body=body,
        )
    ).parsed
