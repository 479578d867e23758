from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.application_import_request import ApplicationImportRequest
from ...models.application_import_result import ApplicationImportResult
from ...types import Response


def _get_kwargs(
    *,
    body: ApplicationImportRequest,
) -> dict[str, Any]:
    headers: dict[str, Any] = {}

    _kwargs: dict[str, Any] = {
        "method": "post",
        "url": "/api/v1/applications/import/",
    }

    _kwargs["files"] = body.to_multipart()

    headers["Content-Type"] = "multipart/form-data; boundary=+++"

    _kwargs["headers"] = headers
    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> ApplicationImportResult | None:
    if response.status_code == 201:
        response_201 = ApplicationImportResult.from_dict(response.json())

        return response_201

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[ApplicationImportResult]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    body: ApplicationImportRequest,
) -> Response[ApplicationImportResult]:
    """Create an application from an uploaded DAG file: continuum JSON, WfCommons WfFormat 1.5, Pegasus
    DAX,
    Kasahara STG (reader ``options`` such as ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5}``) or
    the
    thesis simulator's CSV. The format is ``format``, else the file extension's, else guessed.

    Args:
        body (ApplicationImportRequest): Upload a DAG file: continuum JSON, WfCommons WfFormat
            1.5, Pegasus DAX, Kasahara STG or the thesis CSV.

            The format is ``format`` when given, else the file name's (``.stg``, ``.dax``/``.xml``,
            ``.csv``), else
            guessed from the content. ``options`` (a JSON object) go to the reader, e.g. STG's
            ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5, "seed": 7}``.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ApplicationImportResult]
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
    body: ApplicationImportRequest,
) -> ApplicationImportResult | None:
    """Create an application from an uploaded DAG file: continuum JSON, WfCommons WfFormat 1.5, Pegasus
    DAX,
    Kasahara STG (reader ``options`` such as ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5}``) or
    the
    thesis simulator's CSV. The format is ``format``, else the file extension's, else guessed.

    Args:
        body (ApplicationImportRequest): Upload a DAG file: continuum JSON, WfCommons WfFormat
            1.5, Pegasus DAX, Kasahara STG or the thesis CSV.

            The format is ``format`` when given, else the file name's (``.stg``, ``.dax``/``.xml``,
            ``.csv``), else
            guessed from the content. ``options`` (a JSON object) go to the reader, e.g. STG's
            ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5, "seed": 7}``.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ApplicationImportResult
    """

    return sync_detailed(
        client=client,
        body=body,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    body: ApplicationImportRequest,
) -> Response[ApplicationImportResult]:
    """Create an application from an uploaded DAG file: continuum JSON, WfCommons WfFormat 1.5, Pegasus
    DAX,
    Kasahara STG (reader ``options`` such as ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5}``) or
    the
    thesis simulator's CSV. The format is ``format``, else the file extension's, else guessed.

    Args:
        body (ApplicationImportRequest): Upload a DAG file: continuum JSON, WfCommons WfFormat
            1.5, Pegasus DAX, Kasahara STG or the thesis CSV.

            The format is ``format`` when given, else the file name's (``.stg``, ``.dax``/``.xml``,
            ``.csv``), else
            guessed from the content. ``options`` (a JSON object) go to the reader, e.g. STG's
            ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5, "seed": 7}``.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[ApplicationImportResult]
    """

    kwargs = _get_kwargs(
        body=body,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    body: ApplicationImportRequest,
) -> ApplicationImportResult | None:
    """Create an application from an uploaded DAG file: continuum JSON, WfCommons WfFormat 1.5, Pegasus
    DAX,
    Kasahara STG (reader ``options`` such as ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5}``) or
    the
    thesis simulator's CSV. The format is ``format``, else the file extension's, else guessed.

    Args:
        body (ApplicationImportRequest): Upload a DAG file: continuum JSON, WfCommons WfFormat
            1.5, Pegasus DAX, Kasahara STG or the thesis CSV.

            The format is ``format`` when given, else the file name's (``.stg``, ``.dax``/``.xml``,
            ``.csv``), else
            guessed from the content. ``options`` (a JSON object) go to the reader, e.g. STG's
            ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5, "seed": 7}``.

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        ApplicationImportResult
    """

    return (
        await asyncio_detailed(
            client=client,
            body=body,
        )
    ).parsed
