from http import HTTPStatus
from typing import Any

import httpx

from ... import errors
from ...client import AuthenticatedClient, Client
from ...models.paginated_rt_decision_list import PaginatedRTDecisionList
from ...models.rt_decisions_list_outcome import RtDecisionsListOutcome
from ...types import UNSET, Response, Unset


def _get_kwargs(
    *,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    node: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    outcome: RtDecisionsListOutcome | Unset = UNSET,
    pod: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> dict[str, Any]:

    params: dict[str, Any] = {}

    params["cluster"] = cluster

    params["limit"] = limit

    params["namespace"] = namespace

    params["node"] = node

    params["offset"] = offset

    params["ordering"] = ordering

    json_outcome: str | Unset = UNSET
    if not isinstance(outcome, Unset):
        json_outcome = outcome

    params["outcome"] = json_outcome

    params["pod"] = pod

    params["search"] = search

    params = {k: v for k, v in params.items() if v is not UNSET and v is not None}

    _kwargs: dict[str, Any] = {
        "method": "get",
        "url": "/api/v1/rt-decisions/",
        "params": params,
    }

    return _kwargs


def _parse_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> PaginatedRTDecisionList | None:
    if response.status_code == 200:
        response_200 = PaginatedRTDecisionList.from_dict(response.json())

        return response_200

    if client.raise_on_unexpected_status:
        raise errors.UnexpectedStatus(response.status_code, response.content)
    else:
        return None


def _build_response(
    *, client: AuthenticatedClient | Client, response: httpx.Response
) -> Response[PaginatedRTDecisionList]:
    return Response(
        status_code=HTTPStatus(response.status_code),
        content=response.content,
        headers=response.headers,
        parsed=_parse_response(client=client, response=response),
    )


def sync_detailed(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    node: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    outcome: RtDecisionsListOutcome | Unset = UNSET,
    pod: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedRTDecisionList]:
    """The scheduler process's decisions: every node's filter or score on a small cluster, else the top
    candidates, the count of nodes per rejecting filter and an example of each
    (``decision.rejections``);
    any node's verdict on demand (``why-not``).

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        node (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        outcome (RtDecisionsListOutcome | Unset):
        pod (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedRTDecisionList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        limit=limit,
        namespace=namespace,
        node=node,
        offset=offset,
        ordering=ordering,
        outcome=outcome,
        pod=pod,
        search=search,
    )

    response = client.get_httpx_client().request(
        **kwargs,
    )

    return _build_response(client=client, response=response)


def sync(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    node: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    outcome: RtDecisionsListOutcome | Unset = UNSET,
    pod: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedRTDecisionList | None:
    """The scheduler process's decisions: every node's filter or score on a small cluster, else the top
    candidates, the count of nodes per rejecting filter and an example of each
    (``decision.rejections``);
    any node's verdict on demand (``why-not``).

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        node (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        outcome (RtDecisionsListOutcome | Unset):
        pod (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedRTDecisionList
    """

    return sync_detailed(
        client=client,
        cluster=cluster,
        limit=limit,
        namespace=namespace,
        node=node,
        offset=offset,
        ordering=ordering,
        outcome=outcome,
        pod=pod,
        search=search,
    ).parsed


async def asyncio_detailed(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    node: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    outcome: RtDecisionsListOutcome | Unset = UNSET,
    pod: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> Response[PaginatedRTDecisionList]:
    """The scheduler process's decisions: every node's filter or score on a small cluster, else the top
    candidates, the count of nodes per rejecting filter and an example of each
    (``decision.rejections``);
    any node's verdict on demand (``why-not``).

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        node (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        outcome (RtDecisionsListOutcome | Unset):
        pod (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        Response[PaginatedRTDecisionList]
    """

    kwargs = _get_kwargs(
        cluster=cluster,
        limit=limit,
        namespace=namespace,
        node=node,
        offset=offset,
        ordering=ordering,
        outcome=outcome,
        pod=pod,
        search=search,
    )

    response = await client.get_async_httpx_client().request(**kwargs)

    return _build_response(client=client, response=response)


async def asyncio(
    *,
    client: AuthenticatedClient,
    cluster: int | Unset = UNSET,
    limit: int | Unset = UNSET,
    namespace: str | Unset = UNSET,
    node: str | Unset = UNSET,
    offset: int | Unset = UNSET,
    ordering: str | Unset = UNSET,
    outcome: RtDecisionsListOutcome | Unset = UNSET,
    pod: str | Unset = UNSET,
    search: str | Unset = UNSET,
) -> PaginatedRTDecisionList | None:
    """The scheduler process's decisions: every node's filter or score on a small cluster, else the top
    candidates, the count of nodes per rejecting filter and an example of each
    (``decision.rejections``);
    any node's verdict on demand (``why-not``).

    Args:
        cluster (int | Unset):
        limit (int | Unset):
        namespace (str | Unset):
        node (str | Unset):
        offset (int | Unset):
        ordering (str | Unset):
        outcome (RtDecisionsListOutcome | Unset):
        pod (str | Unset):
        search (str | Unset):

    Raises:
        errors.UnexpectedStatus: If the server returns an undocumented status code and Client.raise_on_unexpected_status is True.
        httpx.TimeoutException: If the request takes longer than Client.timeout.

    Returns:
        PaginatedRTDecisionList
    """

    return (
        await asyncio_detailed(
            client=client,
            cluster=cluster,
            limit=limit,
            namespace=namespace,
            node=node,
            offset=offset,
            ordering=ordering,
            outcome=outcome,
            pod=pod,
            search=search,
        )
    ).parsed
