"""A stored cluster and its Kubernetes API: the client built from its kubeconfig, and node sync.

The gateway (:mod:`apps.kube.gateway`) reads the API and returns plain data; this module owns the
ComputeNode rows and writes what the API says into them. Idempotent: syncing twice leaves the database as
the first call did.
"""

from __future__ import annotations

from django.db import transaction
from django.utils import timezone

from apps.kube import gateway
from apps.kube.gateway import KubeError, Progress

from .models import Cluster, ComputeNode
from .nodes import record_node_status, status_of


def api_client_for(cluster: Cluster, pool: int | None = None):
    """An API client for ``cluster`` from its validated kubeconfig and context (no global state). The one
    builder every caller uses (schedule pushes, container pushes, RT-Kube, HEFT4K); ``pool``: see
    :func:`apps.kube.connect.api_client`."""
    return gateway.api_client(cluster.kubeconfig, cluster.kube_context, name=cluster.name, pool=pool)


def target_for(cluster: Cluster):
    """The cluster's validated API target (see :func:`apps.kube.connect.target`)."""
    return gateway.target(cluster.kubeconfig, cluster.kube_context, name=cluster.name)


#: node_fields' capacity keys -> the columns that keep what Kubernetes reports.
REPORTED = {"cpu": "reported_cpu", "memory_mib": "reported_memory_mib", "storage_mib": "reported_storage_mib"}


def row_fields(fields: dict, source: str) -> dict:
    """The ComputeNode columns a node's API fields set. The reported capacity always goes to ``reported_*``;
    it becomes the planning capacity (``cpu``, ``memory_mib``, ``storage_mib``) only for a node whose capacity
    is ``reported`` (found by sync): a declared capacity (the cluster file's board) stays the planning input,
    since an emulated node (a kubemark hollow node: 1 CPU, 3840 MiB) or a partly allocatable one reports less."""
    out = {k: v for k, v in fields.items() if k not in REPORTED}
    for key, column in REPORTED.items():
        if key in fields:
            out[column] = fields[key]
            if source == ComputeNode.Capacity.REPORTED:
                out[key] = fields[key]
    return out


def sync_nodes(cluster: Cluster, progress: Progress | None = None) -> dict:
    """Create/update the cluster's ComputeNode rows from its API; nodes gone from the API become NotReady.
    Labels, taints, Ready and architecture come from the API; capacity as :func:`row_fields` says (a node
    created here gets the reported capacity as its planning capacity, a declared one keeps its own).

    Returns counts: ``{"nodes", "created", "updated", "unchanged", "gone"}``.
    """
    api_client = api_client_for(cluster)
    server = api_client.configuration.host
    try:
        with api_client:
            items = gateway.list_nodes(api_client)
    except gateway.API_ERRORS as exc:
        raise KubeError(f"cluster {cluster.name!r}: {gateway.describe(exc, server)}") from exc
    if progress:
        progress(50, f"read {len(items)} nodes")
    counts = {"nodes": len(items), "created": 0, "updated": 0, "unchanged": 0, "gone": 0}
    seen = set()
    with transaction.atomic():
        existing = {n.name: n for n in cluster.nodes.select_for_update()}
        for node in items:
            name = node["metadata"]["name"]
            seen.add(name)
            row = existing.get(name)
            if row is None:
                source = ComputeNode.Capacity.REPORTED
                fields = row_fields(gateway.node_fields(node), source)
                ComputeNode.objects.create(cluster=cluster, name=name, capacity_source=source, **fields)
                counts["created"] += 1
                continue
            fields = row_fields(gateway.node_fields(node), row.capacity_source)
            if any(getattr(row, k) != v for k, v in fields.items()):
                for key, value in fields.items():
                    setattr(row, key, value)
                row.save(update_fields=list(fields))
                counts["updated"] += 1
            else:
                counts["unchanged"] += 1
        for name in existing:
            # Kept, not deleted: links, schedules and history still refer to it; NotReady by the one rule.
            if name not in seen and record_node_status(cluster, name, status_of(None)) is not None:
                counts["gone"] += 1
        cluster.last_synced = timezone.now()
        cluster.save(update_fields=["last_synced"])
    return counts
