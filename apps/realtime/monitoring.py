"""The cluster-level monitor: store missed-deadline reports and reconcile each one (thesis 3.4, Fig. 3.36).

Reports arrive over REST (a robot fleet's batch) or as updates of Monitoring custom objects; both go through
:func:`ingest`. Storing is two bulk statements (every report, then the latest counters per container); the
request is acknowledged only after them. Only a report over a threshold (the engine's ``is_violation``) costs
more, and it is handled before the batch is stored, since the eviction is on the clock: :func:`reconcile` locks the
node row (one reconcile per node at a time), reads the pods on the node from the RT scheduler's ledger
(:class:`~apps.realtime.models.RTPod`), and lets the engine's ``ClusterMonitor`` pick the victim by the
cluster's policy. Then, outside the transaction, the node is tainted and the victim deleted with grace
period 0 (taint first, as Fig. 3.36 does, so that the victim's replacement cannot land on the node again).
A pod that no controller owns is recreated by us, as its ReplicaSet would, when the policy says so.

Timestamps of Eq. 3.19 are stored on the :class:`~apps.realtime.models.RTEvent`: the crossing miss and the
report's sending (monitor's clock, when the report carries ``missAt``/``sentAt``), its reception, the end of
the reconcile, the eviction sent and answered.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any

from django.db import connection, transaction
from django.db.models import Q
from django.utils import timezone

from apps.clusters.models import Cluster, ComputeNode
from continuum.engine.errors import InputError
from continuum.engine.rt_victims import (
    ClusterMonitor,
    ContainerInfo,
    MonitorPolicy,
    NodeCapacity,
    is_violation,
    response_time,
)
from continuum.engine.rt_victims import (
    MonitoringReport as EngineReport,
)

from .kube import KUBE_ERRORS, has_api, kube_for, problem, replacement_pod
from .models import DNS_SUBDOMAIN, Monitoring, MonitoringReport, NodeTaint, RTEvent, RTPod, RTPolicy

log = logging.getLogger(__name__)
#: Largest batch one request may carry.
MAX_BATCH = 5000


@dataclass
class Report:
    """One validated report (Listing 3.37 plus the optional ``pod``, ``sentAt`` and ``missAt``)."""

    name: str
    node: str
    container: str
    pod: str
    missed_period: int
    missed_total: int
    sent_at: datetime | None = None
    miss_at: datetime | None = None


# ---- parsing -------------------------------------------------------------------------------------------------
def _stamp(value: Any, where: str, key: str) -> datetime | None:
    """RFC 3339 text or seconds since the epoch."""
    if value is None or value == "":
        return None
    if isinstance(value, bool):
        raise InputError(f"{where}: {key} must be an RFC 3339 time or seconds since the epoch", key)
    if isinstance(value, int | float):
        if not math.isfinite(value):
            raise InputError(f"{where}: {key} must be finite", key)
        try:
            return datetime.fromtimestamp(value, UTC)
        except (OverflowError, OSError, ValueError) as exc:  # beyond year 9999 (or the platform's time_t)
            raise InputError(f"{where}: {key} {value!r} is not a time this system can represent", key) from exc
    if isinstance(value, str):
        try:
            stamp = datetime.fromisoformat(value.replace("Z", "+00:00"))
        except ValueError:
            stamp = None
        if stamp is not None:
            return stamp if stamp.tzinfo else stamp.replace(tzinfo=UTC)
    raise InputError(f"{where}: {key} {value!r} is not an RFC 3339 time or seconds since the epoch", key)


def parse_report(raw: Any, index: int) -> Report:
    """A Monitoring object or its bare ``spec``; InputError naming ``reports[index]`` and the field."""
    where = f"reports[{index}]"
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a Monitoring object or its spec", "reports")
    if "kind" in raw and raw.get("kind") != "Monitoring":
        raise InputError(f"{where}: kind {raw.get('kind')!r} is not Monitoring", "reports")
    try:
        report = EngineReport.from_dict(raw, 0.0)
    except InputError as exc:
        raise InputError(f"{where}: {exc}", "reports") from exc
    spec = raw.get("spec", raw)
    pod = spec.get("pod") or ""
    if not isinstance(pod, str):
        raise InputError(f"{where}: spec.pod must be a pod name", "reports")
    meta = raw.get("metadata") if isinstance(raw.get("metadata"), Mapping) else {}
    name = meta.get("name") or (f"{pod}-{report.container}" if pod else f"{report.container}-{report.node}")
    if not isinstance(name, str) or len(name) > 253 or not DNS_SUBDOMAIN.match(name.lower()):
        raise InputError(f"{where}: metadata.name {name!r} is not a DNS subdomain name", "reports")
    try:
        sent = _stamp(spec.get("sentAt"), where, "sentAt")
        miss = _stamp(spec.get("missAt"), where, "missAt")
    except InputError as exc:
        raise InputError(str(exc), "reports") from exc
    return Report(name.lower(), report.node, report.container, pod, report.missed_period, report.missed_total,
                  sent, miss)  # fmt: skip


def parse_batch(payload: Any) -> list[Report]:
    """``{"reports": [...]}``, a list, or one report; every report is validated before anything is stored."""
    if isinstance(payload, Mapping) and "reports" in payload:
        items = payload["reports"]
    elif isinstance(payload, Mapping):
        items = [payload]
    else:
        items = payload
    if not isinstance(items, list) or not items:
        raise InputError("reports must be a non-empty list of Monitoring objects", "reports")
    if len(items) > MAX_BATCH:
        raise InputError(f"at most {MAX_BATCH} reports per request, got {len(items)}", "reports")
    return [parse_report(raw, i) for i, raw in enumerate(items)]


# ---- storing -------------------------------------------------------------------------------------------------
REPORT_COLUMNS = ("cluster_id", "name", "node", "container_name", "pod", "missed_period", "missed_total", "violation",
                  "sent_at", "miss_at", "received_at", "source")  # fmt: skip
LATEST_COLUMNS = ("cluster_id", "name", "node_id", "container_name", "pod", "missed_period", "missed_total",
                  "received_at", "kube_synced", "resource_version")  # fmt: skip


def insert_rows(
    model, columns: Sequence[str], rows: Sequence[tuple], conflict: Sequence[str] = (), update: Sequence[str] = ()
) -> None:
    """One INSERT of many rows (an upsert with ``conflict``/``update``).

    On PostgreSQL the values travel as one array per column (``unnest``), so the statement text is the same
    for every batch (the driver parses and the server plans it once); elsewhere a multi-row VALUES list.
    """
    if not rows:
        return
    qn = connection.ops.quote_name
    cols = ", ".join(qn(c) for c in columns)
    if connection.vendor == "postgresql":
        fields = {f.column: f for f in model._meta.concrete_fields}
        arrays = ", ".join(f"%s::{fields[c].db_type(connection)}[]" for c in columns)
        sql = f"INSERT INTO {qn(model._meta.db_table)} ({cols}) SELECT * FROM unnest({arrays})"
        params = [list(col) for col in zip(*rows, strict=True)]
    else:
        one = "(" + ", ".join(["%s"] * len(columns)) + ")"
        sql = f"INSERT INTO {qn(model._meta.db_table)} ({cols}) VALUES " + ", ".join([one] * len(rows))
        params = [v for row in rows for v in row]
    if conflict:
        sets = ", ".join(f"{qn(c)} = EXCLUDED.{qn(c)}" for c in update)
        sql += f" ON CONFLICT ({', '.join(qn(c) for c in conflict)}) DO UPDATE SET {sets}"
    with connection.cursor() as cursor:
        cursor.execute(sql, params)


def ingest(
    cluster: Cluster,
    reports: Sequence[Report],
    source: str = MonitoringReport.Source.REST,
    policy: RTPolicy | None = None,
    received_at: datetime | None = None,
) -> dict[str, Any]:
    """Store the reports and reconcile each one over a threshold; returns what happened.

    Raises InputError (nothing stored) when a report names a node the cluster does not have.
    """
    received = received_at or timezone.now()
    policy = policy or RTPolicy.for_cluster(cluster)
    monitor_policy = policy.monitor_policy()
    node_ids = dict(ComputeNode.objects.filter(cluster=cluster).values_list("name", "id"))
    for i, r in enumerate(reports):
        if r.node not in node_ids:
            raise InputError(f"reports[{i}]: node {r.node!r} is not a node of cluster {cluster.name!r}", "reports")
    violations = []
    rows = []
    stamp = connection.ops.adapt_datetimefield_value
    at = stamp(received)
    for r in reports:
        trigger = is_violation(EngineReport(r.node, r.container, r.missed_period, r.missed_total), monitor_policy)
        if trigger:
            violations.append((r, trigger))
        rows.append((cluster.pk, r.name, r.node, r.container, r.pod, r.missed_period,
                     r.missed_total, trigger or "", stamp(r.sent_at), stamp(r.miss_at), at, source))  # fmt: skip
    latest: dict[str, tuple] = {}
    synced = source == MonitoringReport.Source.KUBE
    for r in reports:  # the last report of a container in the batch wins
        latest[r.name] = (cluster.pk, r.name, node_ids[r.node], r.container, r.pod, r.missed_period, r.missed_total,
                          at, synced, "")  # fmt: skip
    # The violations first: the eviction is on the clock (Eq. 3.19), the bookkeeping is not. The fleet's
    # request is answered (acknowledged) only once every report is stored, whatever happened before.
    events = []
    for r, trigger in violations:
        event = reconcile(cluster, policy, monitor_policy, r, trigger, received)
        if event is not None:
            events.append(event)
    with transaction.atomic():
        # Two statements per batch, without the ORM's per-object work (this endpoint takes thousands a second).
        insert_rows(MonitoringReport, REPORT_COLUMNS, rows)
        # Sorted, so that concurrent batches lock the rows in the same order (no deadlock).
        insert_rows(Monitoring, LATEST_COLUMNS, [latest[k] for k in sorted(latest)],
                    conflict=("cluster_id", "name"), update=LATEST_COLUMNS[2:-1])  # fmt: skip
    return {
        "accepted": len(reports),
        "violations": len(violations),
        "events": [event_summary(e) for e in events],
    }


def event_summary(e: RTEvent) -> dict[str, Any]:
    return {
        "id": e.pk,
        "kind": e.kind,
        "node": e.node,
        "container": e.container,
        "trigger": e.trigger,
        "victim": e.victim or None,
        "message": e.message,
        "eviction_error": e.eviction_error or None,
        "response_ms": e.response_ms,
    }


# ---- reconcile ----------------------------------------------------------------------------------------------
def _match(pods: Sequence[RTPod], r: Report) -> tuple[RTPod | None, str]:
    if r.pod:
        hit = [p for p in pods if p.name == r.pod or p.key == r.pod]
        return (hit[0], "") if hit else (None, f"pod {r.pod!r} is not running on node {r.node!r}")
    hit = [
        p
        for p in pods
        if r.container in (p.container_name, p.name) or (p.realtime_id and p.realtime.name == r.container)
    ]
    if len(hit) == 1:
        return hit[0], ""
    if not hit:
        return None, f"no pod of container {r.container!r} is known on node {r.node!r}"
    return None, f"{len(hit)} pods on node {r.node!r} run a container {r.container!r}: the report must name its pod"


def _traffic(policy: RTPolicy, pods: Sequence[RTPod]) -> dict[str, float]:
    """The policy's traffic (keyed by pod or RealTime names) re-keyed by the pods' keys."""
    if not policy.traffic:
        return {}
    aliases: dict[str, list[str]] = {}
    for p in pods:
        for alias in {p.key, p.name, p.realtime.name if p.realtime_id else None} - {None}:
            aliases.setdefault(alias, []).append(p.key)
    out: dict[str, float] = {}
    for key, value in policy.traffic.items():
        a, _, b = str(key).partition("|")
        for ka in aliases.get(a, []):
            for kb in aliases.get(b, []):
                out[f"{ka}|{kb}"] = out.get(f"{ka}|{kb}", 0.0) + float(value)
    return out


def _alert_recently(cluster: Cluster, container: str, since: datetime) -> bool:
    return RTEvent.objects.filter(
        cluster=cluster, container=container, kind=RTEvent.Kind.ALERT, received_at__gte=since
    ).exists()


def reconcile(
    cluster: Cluster,
    policy: RTPolicy,
    monitor_policy: MonitorPolicy,
    r: Report,
    trigger: str,
    received: datetime,
) -> RTEvent | None:
    """Reconcile one report over a threshold: an eviction, an alert, or nothing (cooldown, repeated alert)."""
    now_s = received.timestamp()
    with transaction.atomic():
        node = ComputeNode.objects.select_for_update().get(cluster=cluster, name=r.node)
        pods = list(
            RTPod.objects.filter(cluster=cluster, node=r.node, deleted_at__isnull=True).select_related("realtime")
        )
        violator, problem = _match(pods, r)
        base = {
            "cluster": cluster,
            "node": r.node,
            "trigger": trigger,
            "missed_period": r.missed_period,
            "missed_total": r.missed_total,
            "policy": monitor_policy.eviction_policy,
            "miss_at": r.miss_at,
            "sent_at": r.sent_at,
            "received_at": received,
        }
        if violator is None:
            container = f"{r.node}/{r.container}"
            if _alert_recently(cluster, container, received - timedelta(seconds=monitor_policy.cooldown_time)):
                return None
            return RTEvent.objects.create(
                kind=RTEvent.Kind.ALERT, container=container, message=problem, reconcile_done_at=timezone.now(), **base
            )
        infos = [
            ContainerInfo(p.key, p.criticality, p.stateless, max(p.cpu, p.utilization or 0.0), p.memory_mib)
            for p in pods
        ]
        monitor = ClusterMonitor(monitor_policy)
        # The monitor's only state, the last action per container, matters for the total trigger's cooldown.
        last = None
        if trigger == "total":
            last = (
                RTEvent.objects.filter(cluster=cluster, container=violator.key)
                .order_by("-received_at")
                .values_list("received_at", "missed_total")
                .first()
            )
        if last is not None:
            monitor.last_action[violator.key] = (last[0].timestamp(), last[1])
        report = EngineReport(r.node, violator.key, r.missed_period, r.missed_total, now_s)
        decision = monitor.reconcile(
            report, infos, NodeCapacity(node.cpu or 1.0, float(node.memory_mib or 1)), _traffic(policy, pods), now_s
        )
        if decision.skipped:
            return None
        done = timezone.now()
        base.update(container=violator.key, pod=violator.key, candidates=list(decision.candidates))
        if decision.victim is None:
            if _alert_recently(cluster, violator.key, received - timedelta(seconds=monitor_policy.cooldown_time)):
                return None
            return RTEvent.objects.create(
                kind=RTEvent.Kind.ALERT,
                message=decision.alert or "",
                decision=decision.to_dict(),
                reconcile_done_at=done,
                **base,
            )
        victim = next(p for p in pods if p.key == decision.victim)
        event = RTEvent(
            kind=RTEvent.Kind.EVICTION,
            victim=victim.key,
            message=f"{violator.key} missed {r.missed_period} deadlines in the period ({r.missed_total} in total)",
            decision=decision.to_dict(),
            reconcile_done_at=done,
            **base,
        )
        taint = decision.taint
        expires = datetime.fromtimestamp(taint.until, UTC) if taint and taint.until is not None else done
        node_taint = NodeTaint(cluster=cluster, node=node, key=taint.key, value=taint.value, effect=taint.effect,
                               expires_at=expires)  # fmt: skip
        # Still holding the node's row lock (one reconcile per node at a time), the API calls come first: the
        # eviction is on the clock (Eq. 3.19), the bookkeeping below is not.
        deleted = _evict(cluster, event, victim, node_taint)
        _response(event)
        event.save()
        node_taint.event = event
        node_taint.save()
        if not (event.eviction_sent_at and event.eviction_error):  # evicted (or decided, on a model-only cluster)
            RTPod.objects.filter(pk=victim.pk).update(deleted_at=event.eviction_done_at or done)
        if not any(t.get("key") == taint.key and t.get("effect") == taint.effect for t in node.taints):
            node.taints = [*node.taints, node_taint.as_dict()]
            node.save(update_fields=["taints"])
    if deleted and not victim.owned and policy.recreate_orphans:
        _recreate(cluster, event, victim, deleted)
    return event


def _evict(cluster: Cluster, event: RTEvent, victim: RTPod, taint: NodeTaint) -> dict | None:
    """Taint the node, then delete the victim with grace period 0; records the times and errors on ``event`` and
    ``taint`` (not saved). Returns the deleted pod as the API answered it."""
    if not has_api(cluster):
        event.eviction_error = "model-only cluster (no kubeconfig): nothing to evict"
        return None
    kube = kube_for(cluster)
    try:
        kube.set_taint(event.node, taint.as_dict())
        taint.applied_at = timezone.now()
    except KUBE_ERRORS as exc:
        taint.error = problem(exc)[:500]
    event.eviction_sent_at = timezone.now()
    try:
        deleted = kube.delete_pod(victim.namespace, victim.name, victim.uid or None)
    except KUBE_ERRORS as exc:
        event.eviction_error = problem(exc)[:1000]
        return None
    event.eviction_done_at = timezone.now()
    if deleted is None:
        event.message = f"{event.message}; {victim.key} was gone already"[:1000]
    return deleted


def _recreate(cluster: Cluster, event: RTEvent, victim: RTPod, deleted: dict) -> None:
    """A pod no controller owns would be lost: recreate it (from the DELETE's answer), as a ReplicaSet would."""
    try:
        created = kube_for(cluster).create_pod(victim.namespace, replacement_pod(deleted))
    except KUBE_ERRORS as exc:
        event.eviction_error = f"evicted, but the replacement was refused: {problem(exc)}"[:1000]
        RTEvent.objects.filter(pk=event.pk).update(eviction_error=event.eviction_error)
        return
    event.recreated = created["metadata"]["name"]
    RTEvent.objects.filter(pk=event.pk).update(recreated=event.recreated)
    RTPod.objects.filter(pk=victim.pk).update(
        uid=created["metadata"].get("uid", ""), node="", bound_at=None, deleted_at=None, phase="Pending"
    )


def _response(event: RTEvent) -> None:
    """Eq. 3.19's components (ms). Monitor-side stamps count only when consistent with the server's clock."""
    received = event.received_at.timestamp()
    sent = event.sent_at.timestamp() if event.sent_at else None
    if sent is not None and sent > received:
        sent = None  # the monitor's clock runs ahead of ours: its transfer time cannot be measured
    miss = event.miss_at.timestamp() if event.miss_at else None
    if miss is not None and miss > (sent if sent is not None else received):
        miss = None
    kill_sent = event.eviction_sent_at.timestamp() if event.eviction_sent_at else None
    kill_done = event.eviction_done_at.timestamp() if event.eviction_done_at else None
    if kill_sent is None:
        event.response = {}
        event.response_ms = None
        return
    kill_done = kill_done if kill_done is not None else kill_sent
    s = sent if sent is not None else received
    parts = response_time(miss if miss is not None else s, s, received, kill_sent, kill_done)
    measured = ["reconcile", "trans_kill"]
    if sent is not None:
        measured.append("trans_json")
    if miss is not None:
        measured.append("update_wait")
    event.response = {k: round(v * 1000, 3) for k, v in parts.to_dict().items()} | {"measured": measured}
    event.response_ms = round((kill_sent - received) * 1000, 3)


# ---- timed taints -----------------------------------------------------------------------------------------
def lift_expired_taints(cluster: Cluster | None = None, now: datetime | None = None) -> int:
    """Remove taints whose time is up, from the API and from the node rows; returns how many were lifted.

    A node keeps the taint while another, later-expiring taint with the same key is still active on it.
    """
    now = now or timezone.now()
    due = NodeTaint.objects.filter(lifted_at__isnull=True, expires_at__lte=now).select_related("node", "cluster")
    if cluster is not None:
        due = due.filter(cluster=cluster)
    lifted = 0
    for taint in due:
        still = NodeTaint.objects.filter(
            node=taint.node, key=taint.key, effect=taint.effect, lifted_at__isnull=True, expires_at__gt=now
        ).exists()
        if not still:
            if has_api(taint.cluster):
                try:
                    kube_for(taint.cluster).set_taint(taint.node.name, taint.as_dict(), present=False)
                except KUBE_ERRORS as exc:
                    NodeTaint.objects.filter(pk=taint.pk).update(error=problem(exc)[:500])
                    continue  # try again next time
            with transaction.atomic():
                node = ComputeNode.objects.select_for_update().get(pk=taint.node_id)
                kept = [t for t in node.taints if not (t.get("key") == taint.key and t.get("effect") == taint.effect)]
                if kept != node.taints:
                    node.taints = kept
                    node.save(update_fields=["taints"])
        NodeTaint.objects.filter(pk=taint.pk).update(lifted_at=now)
        lifted += 1
    return lifted


def next_taint_expiry(cluster: Cluster) -> float | None:
    """Seconds until the next active taint of the cluster expires (None: no active taint)."""
    nxt = (
        NodeTaint.objects.filter(cluster=cluster, lifted_at__isnull=True)
        .order_by("expires_at")
        .values_list("expires_at", flat=True)
        .first()
    )
    return None if nxt is None else max(0.0, nxt.timestamp() - time.time())


def active_taints(cluster: Cluster) -> Q:
    return Q(cluster=cluster, lifted_at__isnull=True)
