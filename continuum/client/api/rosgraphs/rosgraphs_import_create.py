from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.ros_graph import RosGraph
from ...models.ros_graph_import_request import RosGraphImportRequest
from ...types import Response


def _get_kwargs(
    *,
    body: RosGraphImportRequest,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/rosgraphs/import/",
    }

    _kwargs["files"] = body.to_multipart()

    headers["Content-Type"] = "multipart/form-data; boundary=+++"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> RosGraph | None:
    if response.status_code == 201:
        response_201 = RosGraph.from_dict(response.json())

        return response_201

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
    *,
    client: AuthenticatedClient,
    body: RosGraphImportRequest,
) -> Response[RosGraph]:
    """Create a ROS graph from an uploaded file (contract JSON, Autoware JSON, iRobot topology, .dot).

    Args:
        body (RosGraphImportRequest): Upload a ROS graph: continuum.rosgraph/v1, Autoware
            reference system JSON, iRobot ros2-performance
            topology JSON or an rqt_graph ``.dot``. A bad file is refused whole with the line or
            element at fault.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[RosGraph]
    """

    kwargs = _get_kwargs(
        body=body,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    body: RosGraphImportRequest,
) -> RosGraph | None:
    """Create a ROS graph from an uploaded file (contract JSON, Autoware JSON, iRobot topology, .dot).

    Args:
        body (RosGraphImportRequest): Upload a ROS graph: continuum.rosgraph/v1, Autoware
            reference system JSON, iRobot ros2-performance
            topology JSON or an rqt_graph ``.dot``. A bad file is refused whole with the line or
            element at fault.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        RosGraph
    """

    return sync_detailed(
        client=client,
        body=body,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: RosGraphImportRequest,
) -> Response[RosGraph]:
    """Create a ROS graph from an uploaded file (contract JSON, Autoware JSON, iRobot topology, .dot).

    Args:
        body (RosGraphImportRequest): Upload a ROS graph: continuum.rosgraph/v1, Autoware
            reference system JSON, iRobot ros2-performance
            topology JSON or an rqt_graph ``.dot``. A bad file is refused whole with the line or
            element at fault.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[RosGraph]
    """

    kwargs = _get_kwargs(
        body=body,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    body: RosGraphImportRequest,
) -> RosGraph | None:
    """Create a ROS graph from an uploaded file (contract JSON, Autoware JSON, iRobot topology, .dot).

    Args:
        body (RosGraphImportRequest): Upload a ROS graph: continuum.rosgraph/v1, Autoware
            reference system JSON, iRobot ros2-performance
            topology JSON or an rqt_graph ``.dot``. A bad file is refused whole with the line or
            element at fault.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        RosGraph
    """

    return (
        await asyncio_detailed(
            client=client,
            body=body,
        )
    ).parsed
