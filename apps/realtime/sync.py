"""Two-way mirror between the database and a cluster's Kubernetes API (spec 03 16.2).

- RealTime: rows changed here (``dirty``) are written to the API; objects created or changed in the API
  (a new ``resourceVersion``) are read into rows; an object deleted in the API deletes its row once the
  row has been in sync, and a row never pushed is created in the API. When both sides changed since the
  last sync, the database wins (its change is the newer intent of an operator of this control plane).
- Nodes: an RT node here gets the ``RealTime=RT:NoSchedule`` taint and the criticality/threshold labels in
  the API; a node tainted ``RealTime=RT:NoSchedule`` in the API becomes an RT node here. Neither side ever
  removes what the other added.
- Monitoring: the latest counters of every report received over REST are written to the Monitoring object
  of the container (the other direction, objects updated in the API, is :mod:`.monitoring`'s ingestion).

Every function returns a summary dict; an object that cannot be mirrored (invalid, or refused) is listed
under ``errors`` with the reason and the others carry on.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable
from typing import Any

from django.db import transaction

from apps.clusters.models import Cluster
from continuum.engine.core.errors import InputError
from continuum.engine.rtkube.rt_model import RT_TAINT, realtime_from_dict

from .kube import (
    CRITICALITY_LABEL,
    KUBE_ERRORS,
    MONITORING_GROUP,
    MONITORING_PLURAL,
    MONITORING_VERSION,
    REALTIME_GROUP,
    REALTIME_PLURAL,
    REALTIME_VERSION,
    THRESHOLD_LABEL,
    Kube,
    crd_manifests,
    kube_for,
    problem,
)
from .models import Monitoring, RealTime, RealTimeWcet

ALL_NAMESPACES = "*"
#: Monitoring objects this process wrote, as (cluster id, name, resourceVersion).
OWN_WRITES: deque[tuple[int, str, str]] = deque(maxlen=10_000)
OWN_WRITES_LOCK = threading.Lock()
Progress = Callable[[float, str], None]


def namespaces_of(cluster: Cluster, namespace: str | None) -> str | None:
    """``None`` means every namespace (the API's cluster-wide list)."""
    if namespace == ALL_NAMESPACES:
        return None
    return namespace or cluster.namespace


# ---- RealTime --------------------------------------------------------------------------------------------
def save_from_resource(cluster: Cluster, obj: dict, row: RealTime | None = None) -> RealTime:
    """Create or update a row from a RealTime object (validated like every other input); InputError if invalid."""
    nodes = {n.name: n for n in cluster.nodes.all()}
    meta = obj.get("metadata") or {}
    container = realtime_from_dict(obj, 0, nodes)
    with transaction.atomic():
        if row is None:
            row = RealTime(cluster=cluster, namespace=meta.get("namespace") or cluster.namespace, name=container.name)
        row.criticality = container.criticality
        row.period = container.period
        row.deadline = container.deadline
        row.stateless = container.stateless
        row.cpu = container.cpu
        row.memory_mib = container.memory_mib
        row.uid = meta.get("uid") or ""
        row.resource_version = meta.get("resourceVersion") or ""
        row.dirty = False
        row.sync_state = RealTime.SyncState.SYNCED if row.uid else RealTime.SyncState.LOCAL
        row.sync_error = ""
        row.save()
        row.wcets.all().delete()
        RealTimeWcet.objects.bulk_create(
            RealTimeWcet(realtime=row, node=nodes[node], wcet=w, position=i)
            for i, (node, w) in enumerate(container.wcet.items())
        )
    return row


def push_realtime(row: RealTime, kube: Kube | None = None) -> bool:
    """Write the row to the API (create or replace); records the outcome on the row. True on success."""
    try:
        kube = kube or kube_for(row.cluster)
        kube.ensure_namespace(row.namespace)
        stored = kube.put_object(REALTIME_GROUP, REALTIME_VERSION, REALTIME_PLURAL, row.to_resource())
    except KUBE_ERRORS as exc:
        message = problem(exc)
        RealTime.objects.filter(pk=row.pk).update(sync_state=RealTime.SyncState.ERROR, sync_error=message[:500])
        row.sync_state, row.sync_error = RealTime.SyncState.ERROR, message[:500]
        return False
    row.uid = stored["metadata"].get("uid", "")
    row.resource_version = stored["metadata"].get("resourceVersion", "")
    row.dirty, row.sync_state, row.sync_error = False, RealTime.SyncState.SYNCED, ""
    RealTime.objects.filter(pk=row.pk).update(
        uid=row.uid, resource_version=row.resource_version, dirty=False, sync_state=row.sync_state, sync_error=""
    )
    return True


def delete_realtime_object(row: RealTime) -> str | None:
    """Delete the row's object from the API (best effort); the reason when it could not be done."""
    try:
        kube_for(row.cluster).delete_object(REALTIME_GROUP, REALTIME_VERSION, REALTIME_PLURAL, row.namespace, row.name)
    except KUBE_ERRORS as exc:
        return problem(exc)
    return None


def sync_realtimes(
    cluster: Cluster, kube: Kube, namespace: str | None = None, rows_read: dict | None = None
) -> dict[str, Any]:
    """``rows_read``, when given, receives the rows as read before any change, each with its WCETs (the RT
    scheduler keeps them when the sync changed nothing, rather than reading them again)."""
    ns = namespaces_of(cluster, namespace)
    if ns is not None:
        kube.ensure_namespace(ns)
    objects = kube.list_objects(REALTIME_GROUP, REALTIME_VERSION, REALTIME_PLURAL, ns)
    rows_qs = cluster.realtimes.prefetch_related("wcets__node")
    if ns is not None:
        rows_qs = rows_qs.filter(namespace=ns)
    rows = {(r.namespace, r.name): r for r in rows_qs}
    if rows_read is not None:
        rows_read.update(rows)
    out: dict[str, Any] = {"read": [], "updated": [], "pushed": [], "deleted": [], "errors": {}}
    for obj in objects:
        meta = obj["metadata"]
        key = (meta["namespace"], meta["name"])
        label = f"{key[0]}/{key[1]}"
        row = rows.pop(key, None)
        try:
            if row is None:
                save_from_resource(cluster, obj)
                out["read"].append(label)
            elif row.dirty:
                if push_realtime(row, kube):
                    out["pushed"].append(label)
                else:
                    out["errors"][label] = row.sync_error
            elif row.resource_version != meta.get("resourceVersion"):
                save_from_resource(cluster, obj, row)
                out["updated"].append(label)
        except InputError as exc:
            out["errors"][label] = str(exc)
            if row is not None:
                RealTime.objects.filter(pk=row.pk).update(
                    sync_state=RealTime.SyncState.ERROR, sync_error=f"the API's version is invalid: {exc}"[:500]
                )
            kube.patch_status(REALTIME_GROUP, REALTIME_VERSION, REALTIME_PLURAL, key[0], key[1], {"error": str(exc)})
    for key, row in rows.items():
        label = f"{key[0]}/{key[1]}"
        if row.uid and not row.dirty:
            row.delete()  # deleted in the API after it was in sync
            out["deleted"].append(label)
        elif push_realtime(row, kube):
            out["pushed"].append(label)
        else:
            out["errors"][label] = row.sync_error
    return out


# ---- nodes ----------------------------------------------------------------------------------------------
def sync_node_rt(cluster: Cluster, kube: Kube, api_nodes: list[dict] | None = None) -> dict[str, Any]:
    """``api_nodes``: the API's nodes as known already (the RT scheduler's node informer), else listed."""
    out: dict[str, Any] = {"tainted": [], "marked_rt": [], "errors": {}}
    rows = {n.name: n for n in cluster.nodes.all()}
    rt_taint = {"key": RT_TAINT.key, "value": RT_TAINT.value, "effect": RT_TAINT.effect}
    for node in kube.list_nodes() if api_nodes is None else api_nodes:
        name = node["metadata"]["name"]
        row = rows.get(name)
        if row is None:
            continue
        taints = node.get("spec", {}).get("taints") or []
        has_taint = any(t.get("key") == RT_TAINT.key and t.get("effect") == RT_TAINT.effect for t in taints)
        labels = node["metadata"].get("labels") or {}
        if row.rt:
            want = {THRESHOLD_LABEL: f"{row.rt_capacity:g}"}
            if row.criticality:
                want[CRITICALITY_LABEL] = row.criticality
            if has_taint and all(labels.get(k) == v for k, v in want.items()):
                continue

            def change(obj, want=want):
                obj["metadata"].setdefault("labels", {}).update(want)
                spec = obj.setdefault("spec", {})
                current = spec.get("taints") or []
                if not any(t.get("key") == RT_TAINT.key and t.get("effect") == RT_TAINT.effect for t in current):
                    spec["taints"] = [*current, rt_taint]
                return True

            try:
                kube.update_node(name, change)
                out["tainted"].append(name)
            except KUBE_ERRORS as exc:
                out["errors"][name] = problem(exc)
        elif has_taint:
            row.rt = True
            fields = ["rt"]
            if not row.criticality and labels.get(CRITICALITY_LABEL) in ("A", "B", "C"):
                row.criticality = labels[CRITICALITY_LABEL]
                fields.append("criticality")
            if row.rt_threshold is None and labels.get(THRESHOLD_LABEL):
                try:
                    row.rt_threshold = float(labels[THRESHOLD_LABEL])
                    fields.append("rt_threshold")
                except ValueError:
                    pass
            if not any(t.get("key") == RT_TAINT.key for t in row.taints):
                row.taints = [*row.taints, rt_taint]
                fields.append("taints")
            row.save(update_fields=fields)
            out["marked_rt"].append(name)
    return out


# ---- Monitoring ---------------------------------------------------------------------------------------------
def push_monitorings(cluster: Cluster, kube: Kube, limit: int = 200) -> dict[str, Any]:
    """Write the counters of containers that reported over REST to their Monitoring objects."""
    out: dict[str, Any] = {"pushed": 0, "errors": {}}
    stale = list(cluster.monitorings.filter(kube_synced=False).select_related("node")[:limit])
    if stale:
        kube.ensure_namespace(cluster.namespace)
    for row in stale:
        try:
            with OWN_WRITES_LOCK:  # the watch must not take our own write for a report
                stored = kube.put_object(
                    MONITORING_GROUP, MONITORING_VERSION, MONITORING_PLURAL, row.to_resource(cluster.namespace)
                )
                rv = stored["metadata"].get("resourceVersion", "")
                OWN_WRITES.append((cluster.pk, row.name, rv))
        except KUBE_ERRORS as exc:
            out["errors"][row.name] = problem(exc)
            continue
        Monitoring.objects.filter(pk=row.pk).update(resource_version=rv)
        # Synced only if no newer report arrived meanwhile.
        Monitoring.objects.filter(
            pk=row.pk, missed_period=row.missed_period, missed_total=row.missed_total, received_at=row.received_at
        ).update(kube_synced=True)
        out["pushed"] += 1
    return out


def own_write(cluster: Cluster, name: str, resource_version: str) -> bool:
    """Whether this process wrote that version of the Monitoring object (so it is not a new report)."""
    with OWN_WRITES_LOCK:
        return (cluster.pk, name, resource_version) in OWN_WRITES


def full_sync(cluster: Cluster, namespace: str | None = None, progress: Progress | None = None) -> dict[str, Any]:
    """CRDs, node RT attributes, RealTime objects and Monitoring counters: what the ``rt_sync`` job does."""
    progress = progress or (lambda p, m: None)
    kube = kube_for(cluster)
    progress(5, "installing the CustomResourceDefinitions")
    crds = kube.install_crds(crd_manifests())
    progress(30, "node taints and labels")
    nodes = sync_node_rt(cluster, kube)
    progress(50, "RealTime objects")
    realtimes = sync_realtimes(cluster, kube, namespace)
    progress(80, "Monitoring objects")
    monitorings = push_monitorings(cluster, kube, limit=10_000)
    return {"crds": crds, "nodes": nodes, "realtimes": realtimes, "monitorings": monitorings}
