from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.admission_report_request import AdmissionReportRequest
from ...models.node_admission import NodeAdmission
from ...types import Response


def _get_kwargs(
    *,
    body: AdmissionReportRequest,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/rt-admissions/",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> NodeAdmission | None:
    if response.status_code == 200:
        response_200 = NodeAdmission.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[NodeAdmission]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: AdmissionReportRequest,
) -> Response[NodeAdmission]:
    """Each node's admissible RT bandwidth and where it comes from. POST (a node agent, with a robot
    token):
    ``{"cluster": id, "node": name, "capacity": CPUs, "cpus": [...], "source": "...", "kernel":
    "..."}``, what
    ``python -m continuum.agent admission`` read from the node's kernel. RT-Kube's filter then admits up
    to it,
    unless the cluster file gives the node an ``rt_threshold`` (which wins); a node that reported
    nothing keeps
    the thesis' M x 0.95 (``rt_capacity_source`` says which).

    Args:
        body (AdmissionReportRequest): What ``python -m continuum.agent admission`` posts.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[NodeAdmission]
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
    body: AdmissionReportRequest,
) -> NodeAdmission | None:
    """Each node's admissible RT bandwidth and where it comes from. POST (a node agent, with a robot
    token):
    ``{"cluster": id, "node": name, "capacity": CPUs, "cpus": [...], "source": "...", "kernel":
    "..."}``, what
    ``python -m continuum.agent admission`` read from the node's kernel. RT-Kube's filter then admits up
    to it,
    unless the cluster file gives the node an ``rt_threshold`` (which wins); a node that reported
    nothing keeps
    the thesis' M x 0.95 (``rt_capacity_source`` says which).

    Args:
        body (AdmissionReportRequest): What ``python -m continuum.agent admission`` posts.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        NodeAdmission
    """

    return sync_detailed(
        client=client,
        body=body,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: AdmissionReportRequest,
) -> Response[NodeAdmission]:
    """Each node's admissible RT bandwidth and where it comes from. POST (a node agent, with a robot
    token):
    ``{"cluster": id, "node": name, "capacity": CPUs, "cpus": [...], "source": "...", "kernel":
    "..."}``, what
    ``python -m continuum.agent admission`` read from the node's kernel. RT-Kube's filter then admits up
    to it,
    unless the cluster file gives the node an ``rt_threshold`` (which wins); a node that reported
    nothing keeps
    the thesis' M x 0.95 (``rt_capacity_source`` says which).

    Args:
        body (AdmissionReportRequest): What ``python -m continuum.agent admission`` posts.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[NodeAdmission]
    """

    kwargs = _get_kwargs(
        body=body,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    body: AdmissionReportRequest,
) -> NodeAdmission | None:
    """Each node's admissible RT bandwidth and where it comes from. POST (a node agent, with a robot
    token):
    ``{"cluster": id, "node": name, "capacity": CPUs, "cpus": [...], "source": "...", "kernel":
    "..."}``, what
    ``python -m continuum.agent admission`` read from the node's kernel. RT-Kube's filter then admits up
    to it,
    unless the cluster file gives the node an ``rt_threshold`` (which wins); a node that reported
    nothing keeps
    the thesis' M x 0.95 (``rt_capacity_source`` says which).

    Args:
        body (AdmissionReportRequest): What ``python -m continuum.agent admission`` posts.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        NodeAdmission
    """

    return (
        await asyncio_detailed(
            client=client,
            body=body,
        )
    ).parsed
