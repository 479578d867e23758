from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.application import Application
from ...models.application_generate_request import ApplicationGenerateRequest
from ...types import Response


def _get_kwargs(
    *,
    body: ApplicationGenerateRequest,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/applications/generate/",
    }

    _kwargs["json"] = body.to_dict()

    headers["Content-Type"] = "application/json"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Application | None:
    if response.status_code == 201:
        response_201 = Application.from_dict(response.json())

        return response_201

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(*, client: AuthenticatedClient | Client, response: httpx.Response) -> Response[Application]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: ApplicationGenerateRequest,
) -> Response[Application]:
    """Create an application from a seeded synthetic DAG (``thesis`` Tree/Linear or ``layered``).

    Args:
        body (ApplicationGenerateRequest): A seeded synthetic DAG: the thesis' ``thesis``
            generator (Tree/Linear OpenVX-like CPU/GPU DAGs,
            spec 01 section 8.2) or the HEFT literature's ``layered`` random graphs (Topcuoglu et al.
            2002).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Application]
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
    body: ApplicationGenerateRequest,
) -> Application | None:
    """Create an application from a seeded synthetic DAG (``thesis`` Tree/Linear or ``layered``).

    Args:
        body (ApplicationGenerateRequest): A seeded synthetic DAG: the thesis' ``thesis``
            generator (Tree/Linear OpenVX-like CPU/GPU DAGs,
            spec 01 section 8.2) or the HEFT literature's ``layered`` random graphs (Topcuoglu et al.
            2002).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Application
    """

    return sync_detailed(
        client=client,
        body=body,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: ApplicationGenerateRequest,
) -> Response[Application]:
    """Create an application from a seeded synthetic DAG (``thesis`` Tree/Linear or ``layered``).

    Args:
        body (ApplicationGenerateRequest): A seeded synthetic DAG: the thesis' ``thesis``
            generator (Tree/Linear OpenVX-like CPU/GPU DAGs,
            spec 01 section 8.2) or the HEFT literature's ``layered`` random graphs (Topcuoglu et al.
            2002).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[Application]
    """

    kwargs = _get_kwargs(
        body=body,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    body: ApplicationGenerateRequest,
) -> Application | None:
    """Create an application from a seeded synthetic DAG (``thesis`` Tree/Linear or ``layered``).

    Args:
        body (ApplicationGenerateRequest): A seeded synthetic DAG: the thesis' ``thesis``
            generator (Tree/Linear OpenVX-like CPU/GPU DAGs,
            spec 01 section 8.2) or the HEFT literature's ``layered`` random graphs (Topcuoglu et al.
            2002).

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Application
    """

    return (
        await asyncio_detailed(
            client=client,
            body=body,
        )
    ).parsed
