"""Nodes: reading them (state, capacity, architecture, taints, labels) and writing their taints.

Nodes are read as the server's JSON (dicts with camelCase keys) and turned into plain data: a state
(:data:`READY`, :data:`NOT_READY`, :data:`UNKNOWN`), the fields a node's API object determines
(:func:`node_fields`) and engine taints (:func:`taints_of`). The app owning the node rows stores them.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Mapping
from decimal import Decimal
from typing import Any

from kubernetes import client
from kubernetes.client.exceptions import ApiException
from kubernetes.utils import parse_quantity

from continuum.engine.core.taints import Taint

from .connect import KubeError, call, read_json

#: A node's state, from its Ready condition.
READY, NOT_READY, UNKNOWN = "Ready", "NotReady", "Unknown"
#: Label keys that carry a node's CPU architecture (the first one present wins).
ARCH_LABELS = ("kubernetes.io/arch", "beta.kubernetes.io/arch")
ARCH_ALIASES = {"x86_64": "amd64", "aarch64": "arm64", "arm64v8": "arm64", "riscv": "riscv64"}
UNSCHEDULABLE_TAINT = {"key": "node.kubernetes.io/unschedulable", "value": "", "effect": "NoSchedule"}
MERGE_PATCH = "application/merge-patch+json"
JSON_PATCH = "application/json-patch+json"


def mib(quantity: str | None) -> int | None:
    """A quantity (``8Gi``, ``512M``...) in whole MiB; ``None`` when absent."""
    if not quantity:
        return None
    return int(parse_quantity(quantity) / Decimal(2**20))


def cores(quantity: str | None) -> float | None:
    """A CPU quantity (``1500m``, ``4``) in cores; ``None`` when absent."""
    return None if not quantity else float(parse_quantity(quantity))


def _arch(obj: Mapping[str, Any]) -> str | None:
    labels = (obj.get("metadata") or {}).get("labels") or {}
    raw = next((labels[k] for k in ARCH_LABELS if labels.get(k)), None)
    if raw is None:
        raw = ((obj.get("status") or {}).get("nodeInfo") or {}).get("architecture")
    if not raw:
        return None
    raw = raw.lower()
    return ARCH_ALIASES.get(raw, raw)[:16]


def node_status(obj: Mapping[str, Any]) -> str:
    """Ready/NotReady/Unknown from the node's Ready condition (no condition at all: Unknown)."""
    for condition in (obj.get("status") or {}).get("conditions") or []:
        if condition.get("type") == "Ready":
            return {"True": READY, "False": NOT_READY}.get(condition.get("status"), UNKNOWN)
    return UNKNOWN


def name_of(obj: Mapping[str, Any]) -> str:
    return (obj.get("metadata") or {}).get("name") or ""


def node_taints(obj: Mapping[str, Any]) -> list[dict[str, str]]:
    """The node's taints as ``{key, value, effect}``; a cordoned node also has the unschedulable taint."""
    spec = obj.get("spec") or {}
    taints = [
        {"key": t.get("key"), "value": t.get("value") or "", "effect": t.get("effect")}
        for t in spec.get("taints") or []
    ]
    if spec.get("unschedulable") and not any(t["key"] == UNSCHEDULABLE_TAINT["key"] for t in taints):
        # A cordoned node: the node lifecycle controller would add this taint; there may be none running.
        taints.append(dict(UNSCHEDULABLE_TAINT))
    return taints


def taints_of(obj: Mapping[str, Any]) -> list[Taint]:
    """The node's taints as engine taints (see :func:`node_taints`)."""
    return [Taint(t["key"], t["value"], t["effect"]) for t in node_taints(obj)]


def node_fields(obj: Mapping[str, Any]) -> dict[str, Any]:
    """What a Kubernetes node determines: ``labels``, ``taints``, ``status`` and, when known, ``arch``,
    ``cpu`` (cores), ``memory_mib``, ``storage_mib`` (capacity). The rest (class, speed, rt...) is Continuum's."""
    capacity = (obj.get("status") or {}).get("capacity") or {}
    fields: dict[str, Any] = {
        "labels": dict((obj.get("metadata") or {}).get("labels") or {}),
        "taints": node_taints(obj),
        "status": node_status(obj),
    }
    for name, value in (
        ("arch", _arch(obj)),
        ("cpu", cores(capacity.get("cpu"))),
        ("memory_mib", mib(capacity.get("memory"))),
        ("storage_mib", mib(capacity.get("ephemeral-storage"))),
    ):
        if value is not None:
            fields[name] = value
    return fields


def allocatable(obj: Mapping[str, Any]) -> tuple[float, float]:
    """The node's allocatable (else capacity) CPU in cores and memory in MiB (0 when not given)."""
    status = obj.get("status") or {}
    alloc = status.get("allocatable") or status.get("capacity") or {}
    return cores(alloc.get("cpu")) or 0.0, float(mib(alloc.get("memory")) or 0)


# -- reading ------------------------------------------------------------------------------------------------


def list_nodes(api_client: client.ApiClient) -> list[dict[str, Any]]:
    """Every node of the API (JSON), retried like every idempotent call (``"list nodes"``)."""
    return list_nodes_with_version(api_client)[0]


def list_nodes_with_version(api_client: client.ApiClient) -> tuple[list[dict[str, Any]], str | None]:
    """The nodes and the list's resourceVersion (where a watch may resume)."""
    core = client.CoreV1Api(api_client)
    listing = call(read_json, core.list_node, what="list nodes", server=api_client.configuration.host) or {}
    return listing.get("items") or [], (listing.get("metadata") or {}).get("resourceVersion")


def node_problems(api_client: client.ApiClient) -> dict[str, str | None]:
    """Every node of the API mapped to why a pod may not go there (``None``: it may)."""
    problems: dict[str, str | None] = {}
    for obj in list_nodes(api_client):
        name = name_of(obj)
        problem = None
        if node_status(obj) == NOT_READY:
            problem = f"node {name!r} is NotReady"
        elif (obj.get("spec") or {}).get("unschedulable"):
            problem = f"node {name!r} is cordoned (unschedulable)"
        problems[name] = problem
    return problems


def ready_nodes(api_client: client.ApiClient) -> set[str]:
    """The names of the nodes whose Ready condition is True."""
    return {name_of(obj) for obj in list_nodes(api_client) if node_status(obj) == READY}


# -- writing taints and labels --------------------------------------------------------------------------------


def _taint_dict(taint: Taint | Mapping[str, Any]) -> dict[str, str]:
    if isinstance(taint, Taint):
        return {"key": taint.key, "value": taint.value or "", "effect": taint.effect}
    return {"key": taint["key"], "value": taint.get("value") or "", "effect": taint["effect"]}


def update_node(api_client: client.ApiClient, name: str, change: Callable[[dict], Any]) -> dict | None:
    """Read the node, let ``change(node)`` edit its JSON (return False for no change), write its labels and
    taints back with optimistic concurrency (the node's resourceVersion), retried on conflicts. Returns the
    node written (or read, when unchanged); ``None`` when there is no such node."""
    core = client.CoreV1Api(api_client)
    server = api_client.configuration.host
    for _ in range(8):
        try:
            node = call(read_json, core.read_node, name, what=f"read node {name}", server=server)
        except ApiException as exc:
            if exc.status == 404:
                return None
            raise
        if change(node) is False:
            return node
        patch = {
            "metadata": {
                "resourceVersion": node["metadata"]["resourceVersion"],
                "labels": node["metadata"].get("labels") or {},
            },
            "spec": {"taints": (node.get("spec") or {}).get("taints") or None},
        }
        try:
            # Idempotent: a retried patch the server had applied answers 409 (resourceVersion), and the loop
            # reads the node again and finds the change made.
            return call(
                read_json, core.patch_node, name, patch, _content_type=MERGE_PATCH, what=f"write node {name}",
                server=server,
            )  # fmt: skip
        except ApiException as exc:
            if exc.status != 409:
                raise
    raise KubeError(f"node {name}: kept changing while we wrote its taints")


def set_taint(
    api_client: client.ApiClient, node: str, taint: Taint | Mapping[str, Any], present: bool = True
) -> dict | None:
    """Add (or remove) one taint, matched on key and effect.

    Adding first tries one JSON-patch append (one round trip: RT-Kube's reconcile phase is on the clock); the
    API refuses it when the node has no taint list or already has that key and effect, and then the node is
    read and rewritten.
    """
    wanted = _taint_dict(taint)
    if present:
        try:
            # Idempotent: a retried append the server had applied is refused (422: the key and effect are
            # there already) and the read-and-rewrite below finds the taint present.
            return call(
                read_json,
                client.CoreV1Api(api_client).patch_node,
                node,
                [{"op": "add", "path": "/spec/taints/-", "value": wanted}],
                _content_type=JSON_PATCH,
                what=f"taint node {node}",
                server=api_client.configuration.host,
            )
        except ApiException as exc:
            if exc.status not in (409, 422):
                raise

    def change(obj: dict):
        spec = obj.setdefault("spec", {})
        taints = list(spec.get("taints") or [])
        same = [t for t in taints if t.get("key") == wanted["key"] and t.get("effect") == wanted["effect"]]
        if present:
            if same and all((t.get("value") or "") == wanted["value"] for t in same):
                return False
            taints = [t for t in taints if t not in same] + [copy.deepcopy(wanted)]
        else:
            if not same:
                return False
            taints = [t for t in taints if t not in same]
        spec["taints"] = taints
        return True

    return update_node(api_client, node, change)
