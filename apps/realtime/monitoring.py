"""The cluster-level monitor: store missed-deadline reports and reconcile each one (thesis 3.4, Fig. 3.36).

Reports arrive over REST (a robot fleet's batch) or as updates of Monitoring custom objects; both go through
:func:`ingest`. A batch is validated whole first (counters within the columns' range, time stamps between 2000 and
2100, text the columns can hold): a bad report is a 400 naming ``reports[i].<field>`` before anything is done. Every
report carries an idempotency key (the client's ``report_id``/``id``, else a digest of its content), unique per
cluster: a retried batch's reports are acknowledged as duplicates and never evicted for twice. Storing is one
statement on PostgreSQL (every new report, then the latest counters per container, in one INSERT with data-modifying
CTEs), two bulk statements elsewhere; the request is acknowledged only after them. Only a report over a threshold
(the engine's ``is_violation``) costs more, and it is handled before the batch is stored, since the eviction is on
the clock: :func:`reconcile` locks the node row (one reconcile per node at a time), reads the pods on the node from
the RT scheduler's ledger (:class:`~apps.realtime.models.RTPod`), and lets the engine's ``ClusterMonitor`` pick the
victim by the cluster's policy. Then, outside the transaction, the node is tainted and the victim deleted with grace
period 0 (taint first, as Fig. 3.36 does, so that the victim's replacement cannot land on the node again).
A pod that no controller owns is recreated by us, as its ReplicaSet would, when the policy says so.

Timestamps of Eq. 3.19 are stored on the :class:`~apps.realtime.models.RTEvent`: the crossing miss and the
report's sending (monitor's clock, when the report carries ``missAt``/``sentAt``), its reception, the end of
the reconcile, the eviction sent and answered.
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
import re
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from functools import cache
from typing import Any

from django.db import connection, transaction
from django.db.models import Q
from django.utils import timezone

from apps.clusters.models import Cluster, ComputeNode
from continuum.engine.core.errors import InputError
from continuum.engine.rtkube.rt_victims import (
    ClusterMonitor,
    ContainerInfo,
    MonitorPolicy,
    NodeCapacity,
    ReconcileDecision,
    is_violation,
    response_time,
)
from continuum.engine.rtkube.rt_victims import (
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
    #: Idempotency key, unique per cluster (see :class:`~apps.realtime.models.MonitoringReport`).
    report_id: str = ""
    #: ``startupOverruns``: overruns before the command was ready (its warm-up), counted apart from the missed
    #: deadlines: stored and shown, never compared with a threshold (a healthy pod is not evicted as it starts).
    startup_overruns: int = 0


# ---- parsing -------------------------------------------------------------------------------------------------
#: Largest counter the columns hold (PositiveIntegerField: a 32-bit integer); checked before anything happens.
COUNT_MAX = 2**31 - 1
#: Monitor time stamps outside this range are refused (1e20 seconds is no time, and would not convert).
STAMP_MIN = datetime(2000, 1, 1, tzinfo=UTC)
STAMP_MAX = datetime(2100, 1, 1, tzinfo=UTC)
_STAMP_RANGE_S = (STAMP_MIN.timestamp(), STAMP_MAX.timestamp())
#: Text columns of a report (node, containerName, pod) hold at most this many characters.
TEXT_MAX = 253
#: A client-chosen report id: printable ASCII without spaces or quotes.
REPORT_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9._:/@+=-]{0,127}")


def _stamp(value: Any, path: str) -> datetime | None:
    """RFC 3339 text or seconds since the epoch, between 2000 and 2100."""
    if value is None or value == "":
        return None
    stamp = None
    if isinstance(value, int | float) and not isinstance(value, bool):
        if not math.isfinite(value):
            raise InputError(f"{path}: must be finite", "reports")
        if _STAMP_RANGE_S[0] <= value < _STAMP_RANGE_S[1]:
            return datetime.fromtimestamp(value, UTC)
    elif isinstance(value, str):
        try:
            stamp = datetime.fromisoformat(value.replace("Z", "+00:00"))
        except ValueError:
            raise InputError(f"{path}: {value!r} is not an RFC 3339 time or seconds since the epoch",
                             "reports") from None  # fmt: skip
        stamp = stamp if stamp.tzinfo else stamp.replace(tzinfo=UTC)
    else:
        raise InputError(f"{path}: must be an RFC 3339 time or seconds since the epoch", "reports")
    if stamp is None or not STAMP_MIN <= stamp < STAMP_MAX:
        raise InputError(f"{path}: {value!r} is not a time between {STAMP_MIN.year} and {STAMP_MAX.year}", "reports")
    return stamp


def _check_fields(spec: Mapping[str, Any], path: str) -> None:
    """What the engine's parser does not check but the columns need: counters within the column's range, text
    within its length and without control characters (PostgreSQL refuses NUL). A report that would fail when
    stored must fail here, before any report of the batch is acted on."""
    for key in ("missedDeadlinesPeriod", "missedDeadlinesTotal"):
        v = spec.get(key)
        if isinstance(v, int) and not isinstance(v, bool) and v > COUNT_MAX:
            raise InputError(f"{path}.{key}: {v} is larger than {COUNT_MAX}", "reports")
    startup = spec.get("startupOverruns")
    if startup is not None and (not isinstance(startup, int) or isinstance(startup, bool)
                                or not 0 <= startup <= COUNT_MAX):  # fmt: skip
        raise InputError(f"{path}.startupOverruns: must be an integer from 0 to {COUNT_MAX}", "reports")
    for key in ("node", "containerName", "pod"):
        v = spec.get(key)
        if isinstance(v, str) and (len(v) > TEXT_MAX or not v.isprintable()):
            raise InputError(f"{path}.{key}: must be at most {TEXT_MAX} printable characters", "reports")


def _report_id(raw: Mapping[str, Any], spec: Mapping[str, Any], where: str) -> str | None:
    """The client's ``report_id``/``reportId``/``id``, on the item or in its spec (None: not given)."""
    sources = ((where, raw),) if spec is raw else ((where, raw), (f"{where}.spec", spec))
    for path, source in sources:
        for key in ("report_id", "reportId", "id"):
            if key not in source or source[key] is None:
                continue
            value = source[key]
            text = str(value) if isinstance(value, int) and not isinstance(value, bool) else value
            if not isinstance(text, str) or not REPORT_ID.fullmatch(text):
                raise InputError(f"{path}.{key}: {value!r} is not a report id (1-128 letters, digits, ._:/@+=-)",
                                 "reports")  # fmt: skip
            return text
    return None


def _content_key(report: Report, meta: Mapping[str, Any]) -> str:
    """The idempotency key of a report without an id: a digest of what it says (and, for a custom object, of
    its uid and resourceVersion), so that the same report posted again has the same key. (``repr`` of a tuple
    of strings and numbers is unambiguous, and cheaper than JSON on this hot path.)"""
    content = (report.name, report.node, report.container, report.pod, report.missed_period, report.missed_total,
               report.sent_at.timestamp() if report.sent_at else None,
               report.miss_at.timestamp() if report.miss_at else None,
               str(meta.get("uid") or ""), str(meta.get("resourceVersion") or ""))  # fmt: skip
    return "sha256:" + hashlib.sha256(repr(content).encode()).hexdigest()


def parse_report(raw: Any, index: int) -> Report:
    """A Monitoring object or its bare ``spec``; InputError naming ``reports[index]`` and the field."""
    where = f"reports[{index}]"
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a Monitoring object or its spec", "reports")
    if "kind" in raw and raw.get("kind") != "Monitoring":
        raise InputError(f"{where}: kind {raw.get('kind')!r} is not Monitoring", "reports")
    spec = raw.get("spec", raw)
    path = f"{where}.spec" if "spec" in raw else where
    if isinstance(spec, Mapping):
        _check_fields(spec, path)
    try:
        report = EngineReport.from_dict(raw, 0.0)
    except InputError as exc:
        raise InputError(f"{where}: {exc}", "reports") from exc
    pod = spec.get("pod") or ""
    if not isinstance(pod, str):
        raise InputError(f"{where}: spec.pod must be a pod name", "reports")
    meta = raw.get("metadata") if isinstance(raw.get("metadata"), Mapping) else {}
    name = meta.get("name") or (f"{pod}-{report.container}" if pod else f"{report.container}-{report.node}")
    if not isinstance(name, str) or len(name) > 253 or not DNS_SUBDOMAIN.match(name.lower()):
        raise InputError(f"{where}: metadata.name {name!r} is not a DNS subdomain name", "reports")
    sent = _stamp(spec.get("sentAt"), f"{path}.sentAt")
    miss = _stamp(spec.get("missAt"), f"{path}.missAt")
    out = Report(name.lower(), report.node, report.container, pod, report.missed_period, report.missed_total,
                 sent, miss, startup_overruns=spec.get("startupOverruns") or 0)  # fmt: skip
    out.report_id = _report_id(raw, spec, where) or _content_key(out, meta)
    return out


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
                  "sent_at", "miss_at", "received_at", "source", "report_id", "startup_overruns")  # fmt: skip
LATEST_COLUMNS = ("cluster_id", "name", "node_id", "container_name", "pod", "missed_period", "missed_total",
                  "received_at", "kube_synced", "resource_version")  # fmt: skip
#: The unique index that makes a replayed report a no-op (``MonitoringReport.Meta.constraints``).
REPORT_KEY = ("cluster_id", "report_id")


def insert_rows(
    model,
    columns: Sequence[str],
    rows: Sequence[tuple],
    conflict: Sequence[str] = (),
    update: Sequence[str] = (),
    returning: str | None = None,
) -> int | list:
    """One INSERT of many rows (an upsert with ``conflict``/``update``; with ``conflict`` alone, rows that
    conflict are skipped); returns how many rows were inserted or updated, or with ``returning`` (a column)
    that column of each of them.

    On PostgreSQL the values travel as one array per column (``unnest``), so the statement text is the same
    for every batch (the driver parses and the server plans it once); elsewhere a multi-row VALUES list.
    """
    if not rows:
        return [] if returning else 0
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
        target = ", ".join(qn(c) for c in conflict)
        if update:
            sets = ", ".join(f"{qn(c)} = EXCLUDED.{qn(c)}" for c in update)
            sql += f" ON CONFLICT ({target}) DO UPDATE SET {sets}"
        else:
            sql += f" ON CONFLICT ({target}) DO NOTHING"
    if returning:
        sql += f" RETURNING {qn(returning)}"
    with connection.cursor() as cursor:
        cursor.execute(sql, params)
        return [row[0] for row in cursor.fetchall()] if returning else cursor.rowcount


def check_nodes(
    cluster: Cluster, reports: Sequence[Report], node_ids: Mapping[str, int] | None = None
) -> Mapping[str, int]:
    """The cluster's node ids by name (``node_ids``: read with the cluster already, see
    :func:`with_node_ids`); InputError naming the first report on a node the cluster lacks."""
    if node_ids is None:
        node_ids = dict(ComputeNode.objects.filter(cluster=cluster).values_list("name", "id"))
    for i, r in enumerate(reports):
        if r.node not in node_ids:
            raise InputError(f"reports[{i}]: node {r.node!r} is not a node of cluster {cluster.name!r}", "reports")
    return node_ids


def with_node_ids(clusters):
    """``clusters`` (a queryset) annotated with their nodes' names and ids (``node_names``, ``node_pks``, in the
    same order) on PostgreSQL: the report endpoint reads the cluster, its policy and its nodes in one round
    trip instead of two. Elsewhere unchanged (:func:`node_ids_of` answers None, :func:`check_nodes` reads)."""
    if connection.vendor != "postgresql":
        return clusters
    from django.contrib.postgres.expressions import ArraySubquery
    from django.db.models import OuterRef

    nodes = ComputeNode.objects.filter(cluster=OuterRef("pk")).order_by("pk")
    return clusters.annotate(node_names=ArraySubquery(nodes.values("name")),
                             node_pks=ArraySubquery(nodes.values("pk")))  # fmt: skip


def node_ids_of(cluster: Cluster) -> dict[str, int] | None:
    """The node ids by name :func:`with_node_ids` read with the cluster (None: not read)."""
    names, pks = getattr(cluster, "node_names", None), getattr(cluster, "node_pks", None)
    return None if names is None or pks is None else dict(zip(names, pks, strict=True))


def ingest(
    cluster: Cluster,
    reports: Sequence[Report],
    source: str = MonitoringReport.Source.REST,
    policy: RTPolicy | None = None,
    received_at: datetime | None = None,
    defer: bool = False,
    node_ids: Mapping[str, int] | None = None,
) -> dict[str, Any]:
    """Store the reports, then reconcile each new one over a threshold (or, with ``defer``, leave that to the
    caller: :func:`reconcile_stored` in the ``continuum.rt_reconcile`` task); returns what happened, with
    ``pending``: the stored violations (report row ids) not reconciled here.

    Raises InputError (nothing stored, nothing done) when a report names a node the cluster does not have;
    every other check was made by :func:`parse_report`. The whole batch, violations included, is stored first
    (one statement on PostgreSQL): a report acknowledged is a report stored, whatever happens to its
    reconcile. A report whose id the cluster has stored (a retried batch) is acknowledged as a duplicate and
    not acted on again: the unique index answers, with no look-up before (``ON CONFLICT DO NOTHING``). A new
    violation is stored with ``reconciled_at`` empty; its reconcile claims it (:func:`reconcile`), so it is
    acted on exactly once, here, in the task, or in the sweep of overdue violations
    (:func:`reconcile_overdue`) if the task's message was lost.
    """
    received = received_at or timezone.now()
    policy = policy or RTPolicy.for_cluster(cluster)
    monitor_policy = policy.monitor_policy()
    node_ids = check_nodes(cluster, reports, node_ids)
    first: dict[str, Report] = {}
    for r in reports:  # the same id twice in one batch: the first one counts
        first.setdefault(r.report_id, r)
    violations, rows = _classify(cluster, first, monitor_policy, received, source)
    new = _store_batch(cluster, first, rows, node_ids, received, source, bool(violations))
    # Decided from the batch in memory: the new reports over a threshold, in batch order.
    claims = [(new[r.report_id], r, trigger, received) for r, trigger in violations if new.get(r.report_id)]
    events = [] if defer else _reconcile_claims(cluster, policy, monitor_policy, claims)
    duplicates = [i for i, r in enumerate(reports) if r.report_id not in new or first[r.report_id] is not r]
    return {
        "accepted": len(reports),
        "stored": len(new),
        "duplicates": duplicates,
        "report_ids": [r.report_id for r in reports],
        "violations": len(claims),
        "events": [event_summary(e) for e in events],
        "pending": [pk for pk, *_ in claims] if defer else [],
    }


def _classify(
    cluster: Cluster, first: Mapping[str, Report], monitor_policy: MonitorPolicy, received: datetime, source: str
) -> tuple[list[tuple[Report, str]], dict[str, tuple]]:
    """The reports over a threshold (with their trigger) and every report's row (``REPORT_COLUMNS``) by id."""
    violations = []
    rows: dict[str, tuple] = {}
    stamp = connection.ops.adapt_datetimefield_value
    at = stamp(received)
    for rid, r in first.items():
        trigger = is_violation(EngineReport(r.node, r.container, r.missed_period, r.missed_total), monitor_policy)
        if trigger:
            violations.append((r, trigger))
        rows[rid] = (cluster.pk, r.name, r.node, r.container, r.pod, r.missed_period, r.missed_total,
                     trigger or "", stamp(r.sent_at), stamp(r.miss_at), at, source, rid,
                     r.startup_overruns)  # fmt: skip
    return violations, rows


def _reconcile_claims(
    cluster: Cluster,
    policy: RTPolicy,
    monitor_policy: MonitorPolicy,
    claims: Sequence[tuple[int, Report, str, datetime]],
    stamps: Mapping[str, float] | None = None,
) -> list[RTEvent]:
    """Reconcile stored violations ``(row id, report, trigger, received)`` in order; the events made. One
    claimed meanwhile by another reconcile (a redelivered task, the sweep) is skipped. ``stamps``: epoch times
    of the stages before the reconcile (the task's ``queued``, ``picked``), kept with each eviction."""
    events = []
    for pk, r, trigger, received in claims:
        try:
            event = reconcile(cluster, policy, monitor_policy, r, trigger, received, claim=pk,
                              stamps=dict(stamps or {}))  # fmt: skip
        except Exception:
            # One row the code cannot handle must not stop the others (issue 25: the sweep aborted its loop over
            # every cluster, every 10 s). Its claim was rolled back with the failure: the next sweep tries again.
            log.exception("reconcile of violation %s of cluster %s failed; skipped", pk, cluster.pk)
            continue
        if event is not DUPLICATE and event is not None:
            events.append(event)
    return events


def reconcile_stored(
    cluster: Cluster,
    report_pks: Sequence[int],
    policy: RTPolicy | None = None,
    stamps: Mapping[str, float] | None = None,
) -> list[RTEvent]:
    """Reconcile the cluster's stored violations among ``report_pks`` that no reconcile has claimed yet (the
    ``continuum.rt_reconcile`` task; rows of another cluster are not looked at)."""
    policy = policy or RTPolicy.for_cluster(cluster)
    rows = (
        MonitoringReport.objects.filter(cluster=cluster, pk__in=list(report_pks), reconciled_at__isnull=True)
        .exclude(violation="")
        .order_by("pk")
    )
    claims = [
        (row.pk, Report(row.name, row.node, row.container_name, row.pod, row.missed_period, row.missed_total,
                        row.sent_at, row.miss_at, row.report_id or ""), row.violation, row.received_at)
        for row in rows
    ]  # fmt: skip
    return _reconcile_claims(cluster, policy, policy.monitor_policy(), claims, stamps)


def reconcile_overdue(older_than_s: float = 30.0, limit: int = 1000) -> int:
    """Reconcile violations stored more than ``older_than_s`` ago and still unclaimed (their task's message was
    lost: a broker down when the report came, a worker killed before it acknowledged); how many were."""
    due = (
        MonitoringReport.objects.filter(
            reconciled_at__isnull=True, received_at__lt=timezone.now() - timedelta(seconds=older_than_s)
        )
        .exclude(violation="")
        .order_by("received_at")
        .values_list("cluster_id", "pk")[:limit]
    )
    by_cluster: dict[int, list[int]] = {}
    for cluster_id, pk in due:
        by_cluster.setdefault(cluster_id, []).append(pk)
    done = 0
    for cluster in Cluster.objects.select_related("rt_policy").filter(pk__in=by_cluster):
        try:
            reconcile_stored(cluster, by_cluster[cluster.pk], policy_of(cluster))
        except Exception:  # this cluster's rows (its policy...): logged, and every other cluster still served
            log.exception("overdue reconcile of cluster %s failed; skipped until the next sweep", cluster.pk)
            continue
        left = MonitoringReport.objects.filter(pk__in=by_cluster[cluster.pk], reconciled_at__isnull=True).count()
        done += len(by_cluster[cluster.pk]) - left
    return done


def policy_of(cluster: Cluster) -> RTPolicy:
    """The cluster's RT policy: the one read with it (``select_related``) if any, else made with defaults."""
    try:
        return cluster.rt_policy
    except RTPolicy.DoesNotExist:
        return RTPolicy.for_cluster(cluster)


def _store_batch(
    cluster: Cluster,
    first: Mapping[str, Report],
    rows: Mapping[str, tuple],
    node_ids: Mapping[str, int],
    received: datetime,
    source: str,
    with_ids: bool,
) -> dict[str, int]:
    """Insert the reports and the latest counters per container; the ids stored new, with their row ids when
    ``with_ids`` (a violation's row is what its reconcile claims; else 0)."""
    at = connection.ops.adapt_datetimefield_value(received)
    synced = source == MonitoringReport.Source.KUBE
    if connection.vendor == "postgresql":
        return _store_batch_pg(first, rows, node_ids, at, synced)
    with transaction.atomic():
        # Two statements per batch, without the ORM's per-object work (this endpoint takes thousands a second).
        inserted = insert_rows(MonitoringReport, REPORT_COLUMNS, list(rows.values()), conflict=REPORT_KEY,
                               returning="report_id")  # fmt: skip
        new = dict.fromkeys(inserted, 0)
        if with_ids and new:
            new.update(
                MonitoringReport.objects.filter(cluster=cluster, report_id__in=list(new)).values_list("report_id", "pk")
            )
        latest: dict[str, tuple] = {}
        for rid, r in first.items():  # the last new report of a container in the batch wins
            if rid in new:
                latest[r.name] = (cluster.pk, r.name, node_ids[r.node], r.container, r.pod, r.missed_period,
                                  r.missed_total, at, synced, "")  # fmt: skip
        # Sorted, so that concurrent batches lock the rows in the same order (no deadlock).
        insert_rows(Monitoring, LATEST_COLUMNS, [latest[k] for k in sorted(latest)],
                    conflict=("cluster_id", "name"), update=LATEST_COLUMNS[2:-1])  # fmt: skip
    return new


def _pg_types(model, columns: Sequence[str]) -> list[str]:
    fields = {f.column: f for f in model._meta.concrete_fields}
    return [fields[c].db_type(connection) for c in columns]


@cache  # the same text for every batch (PostgreSQL only)
def _store_sql() -> str:
    """The batch in one statement (one round trip instead of four: no BEGIN/COMMIT, two INSERTs): the new
    reports (``ON CONFLICT DO NOTHING``: a duplicate id is skipped), then, for each container, its last new
    report in the batch upserted into the latest counters, in name order so that concurrent batches lock the
    rows in the same order. Returns the ids inserted and their row ids."""
    qn = connection.ops.quote_name
    report_types = _pg_types(MonitoringReport, REPORT_COLUMNS)
    node_type = _pg_types(Monitoring, ("node_id",))[0]
    cols = ", ".join(qn(c) for c in REPORT_COLUMNS)
    # The rows travel as one JSON array of arrays: one text parameter for the driver to send (psycopg dumps
    # an array parameter element by element in Python: that was a fifth of the request's CPU).
    fields = [f"(e->>{i})::{t} AS {qn(c)}" for i, (c, t) in enumerate(zip(REPORT_COLUMNS, report_types, strict=True))]
    fields.append(f"(e->>{len(REPORT_COLUMNS)})::{node_type} AS node_ref")
    latest = ", ".join(qn(c) for c in LATEST_COLUMNS)
    sets = ", ".join(f"{qn(c)} = EXCLUDED.{qn(c)}" for c in LATEST_COLUMNS[2:-1])
    return (
        f"WITH src AS (SELECT {', '.join(fields)}, ord FROM json_array_elements(%s::json) WITH ORDINALITY "
        f"AS t(e, ord)), "
        f"ins AS (INSERT INTO {qn(MonitoringReport._meta.db_table)} ({cols}) SELECT {cols} FROM src "
        f"ON CONFLICT ({qn('cluster_id')}, {qn('report_id')}) DO NOTHING "
        f"RETURNING {qn('report_id')}, {qn('id')}), "
        f"latest AS (INSERT INTO {qn(Monitoring._meta.db_table)} ({latest}) "
        f"SELECT DISTINCT ON (src.{qn('name')}) src.{qn('cluster_id')}, src.{qn('name')}, node_ref, "
        f"src.{qn('container_name')}, src.{qn('pod')}, src.{qn('missed_period')}, src.{qn('missed_total')}, "
        f"src.{qn('received_at')}, %s, '' FROM src "
        f"WHERE src.{qn('report_id')} IN (SELECT {qn('report_id')} FROM ins) "
        f"ORDER BY src.{qn('name')}, ord DESC "
        f"ON CONFLICT ({qn('cluster_id')}, {qn('name')}) DO UPDATE SET {sets}) "
        f"SELECT {qn('report_id')}, {qn('id')} FROM ins"
    )


def _store_batch_pg(
    first: Mapping[str, Report],
    rows: Mapping[str, tuple],
    node_ids: Mapping[str, int],
    at: Any,
    synced: bool,
) -> dict[str, int]:
    if not rows:
        return {}
    # Batch order: the ordinality that makes the last report of a container win.
    data = json.dumps([[*rows[rid], node_ids[r.node]] for rid, r in first.items()], default=datetime.isoformat)
    with connection.cursor() as cursor:
        cursor.execute(_store_sql(), [data, synced])
        return dict(cursor.fetchall())


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


#: What :func:`reconcile` returns for a report whose id another request stored meanwhile.
DUPLICATE: Any = object()


def reconcile(
    cluster: Cluster,
    policy: RTPolicy,
    monitor_policy: MonitorPolicy,
    r: Report,
    trigger: str,
    received: datetime,
    claim: int | None = None,
    stamps: dict[str, float] | None = None,
) -> RTEvent | None:
    """Reconcile one report over a threshold: an eviction, an alert, or nothing (cooldown, repeated alert).

    ``claim`` is the stored report's row id: its ``reconciled_at`` is set first, in the same transaction as
    the event, taint and ledger updates, so the report is claimed exactly when its eviction is recorded (a
    reconcile that fails rolls the claim back, and the sweep tries again). If another reconcile claimed it
    already (a redelivered task, the sweep), nothing is done and :data:`DUPLICATE` is returned.

    ``stamps`` (epoch seconds by stage) gets the claim's, the decision's and the taint's times; an eviction keeps
    them, as milliseconds after the report's reception, in ``response["stages"]`` (where the time goes).
    """
    stamps = {} if stamps is None else stamps
    with transaction.atomic():
        if claim is not None and not MonitoringReport.objects.filter(pk=claim, reconciled_at__isnull=True).update(
            reconciled_at=timezone.now()
        ):
            return DUPLICATE
        node = ComputeNode.objects.select_for_update().filter(cluster=cluster, name=r.node).first()
        if node is None:  # deleted after the report was stored: nothing on it to evict, said once (claimed)
            base = _event_fields(cluster, monitor_policy, r, trigger, received)
            gone = f"node {r.node!r} is no longer in the cluster: the violation reported on it was not acted on"
            return _unmatched_alert(cluster, monitor_policy, r, gone, base)
        pods = list(
            RTPod.objects.filter(cluster=cluster, node=r.node, deleted_at__isnull=True).select_related("realtime")
        )
        stamps["claimed"] = time.time()
        violator, reason = _match(pods, r)
        base = _event_fields(cluster, monitor_policy, r, trigger, received)
        if violator is None:
            return _unmatched_alert(cluster, monitor_policy, r, reason, base)
        decision = _decide(cluster, policy, monitor_policy, node, pods, violator, r, trigger, received)
        if decision.skipped:
            return None
        done = timezone.now()
        base.update(container=violator.key, pod=violator.key, candidates=list(decision.candidates))
        if decision.victim is None:
            return _decision_alert(cluster, monitor_policy, violator, decision, done, base)
        victim = next(p for p in pods if p.key == decision.victim)
        event, node_taint = _eviction_records(cluster, node, victim, violator, r, decision, done, base)
        # Still holding the node's row lock (one reconcile per node at a time), the API calls come first: the
        # eviction is on the clock (Eq. 3.19), the bookkeeping below is not.
        deleted = _evict(cluster, event, victim, node_taint, stamps, _tainted_already(node, node_taint))
        _response(event)
        _stages(event, done, stamps)
        _record_eviction(event, node_taint, node, victim, done)
    if deleted and not victim.owned and policy.recreate_orphans:
        _recreate(cluster, event, victim, deleted)
    return event


def _event_fields(
    cluster: Cluster, monitor_policy: MonitorPolicy, r: Report, trigger: str, received: datetime
) -> dict[str, Any]:
    """The fields every event of this report shares, whatever the decision."""
    return {
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


def _cooling_down(cluster: Cluster, monitor_policy: MonitorPolicy, container: str, received: datetime) -> bool:
    """An alert for ``container`` within the cooldown before ``received``: do not repeat it."""
    return _alert_recently(cluster, container, received - timedelta(seconds=monitor_policy.cooldown_time))


def _unmatched_alert(
    cluster: Cluster, monitor_policy: MonitorPolicy, r: Report, reason: str, base: dict[str, Any]
) -> RTEvent | None:
    """The report names no pod we know on the node: an alert saying why (unless one was raised recently)."""
    container = f"{r.node}/{r.container}"[:253]  # the column's length: both parts may be that long
    if _cooling_down(cluster, monitor_policy, container, base["received_at"]):
        return None
    return RTEvent.objects.create(
        kind=RTEvent.Kind.ALERT, container=container, message=reason, reconcile_done_at=timezone.now(), **base
    )


def _decide(
    cluster: Cluster,
    policy: RTPolicy,
    monitor_policy: MonitorPolicy,
    node: ComputeNode,
    pods: Sequence[RTPod],
    violator: RTPod,
    r: Report,
    trigger: str,
    received: datetime,
) -> ReconcileDecision:
    """The engine's ``ClusterMonitor`` decision on the node's pods (victim, candidates, taint, or an alert)."""
    now_s = received.timestamp()
    infos = [
        ContainerInfo(p.key, p.criticality, p.stateless, max(p.cpu, p.utilization or 0.0), p.memory_mib) for p in pods
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
    capacity = NodeCapacity(node.cpu or 1.0, float(node.memory_mib or 1))
    return monitor.reconcile(report, infos, capacity, _traffic(policy, pods), now_s)


def _decision_alert(
    cluster: Cluster,
    monitor_policy: MonitorPolicy,
    violator: RTPod,
    decision: ReconcileDecision,
    done: datetime,
    base: dict,
) -> RTEvent | None:
    """The engine found no victim: an alert with its reason (unless one was raised recently)."""
    if _cooling_down(cluster, monitor_policy, violator.key, base["received_at"]):
        return None
    return RTEvent.objects.create(
        kind=RTEvent.Kind.ALERT,
        message=decision.alert or "",
        decision=decision.to_dict(),
        reconcile_done_at=done,
        **base,
    )


def _eviction_records(
    cluster: Cluster,
    node: ComputeNode,
    victim: RTPod,
    violator: RTPod,
    r: Report,
    decision: ReconcileDecision,
    done: datetime,
    base: dict,
) -> tuple[RTEvent, NodeTaint]:
    """The eviction event and the node's taint, not saved yet (the API calls fill in their times first)."""
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
    return event, node_taint


def _record_eviction(event: RTEvent, node_taint: NodeTaint, node: ComputeNode, victim: RTPod, done: datetime) -> None:
    """Save the event and the taint, retire the victim from the ledger, and list the taint on the node row."""
    event.save()
    node_taint.event = event
    node_taint.save()
    if not (event.eviction_sent_at and event.eviction_error):  # evicted (or decided, on a model-only cluster)
        RTPod.objects.filter(pk=victim.pk).update(deleted_at=event.eviction_done_at or done)
    if not any(t.get("key") == node_taint.key and t.get("effect") == node_taint.effect for t in node.taints):
        node.taints = [*node.taints, node_taint.as_dict()]
        node.save(update_fields=["taints"])


#: An active taint of ours must last this much longer for an eviction to count on it (see :func:`_evict`).
TAINT_MARGIN = timedelta(seconds=2)


def _tainted_already(node: ComputeNode, taint: NodeTaint) -> bool:
    """Whether our own active taint with this key, value and effect is on the node (applied, not lifted, not
    about to expire): then the eviction need not wait for the taint's write (see :func:`_evict`)."""
    wanted = taint.as_dict()
    if not any(all(t.get(k) == v for k, v in wanted.items()) for t in node.taints):
        return False
    return NodeTaint.objects.filter(
        node=node, key=taint.key, value=taint.value, effect=taint.effect, lifted_at__isnull=True,
        applied_at__isnull=False, error="", expires_at__gt=timezone.now() + TAINT_MARGIN,
    ).exists()  # fmt: skip


def _evict(
    cluster: Cluster,
    event: RTEvent,
    victim: RTPod,
    taint: NodeTaint,
    stamps: dict[str, float] | None = None,
    tainted: bool = False,
) -> dict | None:
    """Taint the node, then delete the victim with grace period 0; records the times and errors on ``event`` and
    ``taint`` (not saved). Returns the deleted pod as the API answered it.

    ``tainted``: our active taint is on the node already (an earlier eviction's, lasting): the victim is deleted
    first and the taint confirmed right after (an idempotent write), so the kill does not wait for the
    taint's round trips (a repeated append is refused, then the node is read: three of them). A replacement
    cannot land on the node meanwhile: the taint is there."""
    stamps = {} if stamps is None else stamps
    if not has_api(cluster):
        event.eviction_error = "model-only cluster (no kubeconfig): nothing to evict"
        return None
    kube = kube_for(cluster)
    if not tainted:
        _taint(kube, event.node, taint)
    stamps["tainted"] = time.time()
    event.eviction_sent_at = timezone.now()
    try:
        deleted = kube.delete_pod(victim.namespace, victim.name, victim.uid or None)
    except KUBE_ERRORS as exc:
        event.eviction_error = problem(exc)[:1000]
        deleted = None
    else:
        event.eviction_done_at = timezone.now()
        if deleted is None:
            event.message = f"{event.message}; {victim.key} was gone already"[:1000]
    if tainted:
        _taint(kube, event.node, taint)
    return deleted


def _taint(kube, node: str, taint: NodeTaint) -> None:
    try:
        kube.set_taint(node, taint.as_dict())
        taint.applied_at = timezone.now()
    except KUBE_ERRORS as exc:
        taint.error = problem(exc)[:500]


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


#: The stages of an eviction, in order (``RTEvent.response["stages"]``, ms after the report's reception).
STAGES = ("queued", "picked", "claimed", "decided", "tainted", "sent", "answered")


def _stages(event: RTEvent, decided: datetime, stamps: Mapping[str, float]) -> None:
    """Where the eviction's time went: each stage's time after the report's reception (ms): the message
    published (``queued``), taken by a worker (``picked``), the report claimed and the node's pods read
    (``claimed``), the victim decided, the taint written, the DELETE sent and answered."""
    if not event.response:
        return
    at = dict(stamps, decided=decided.timestamp())
    if event.eviction_sent_at:
        at["sent"] = event.eviction_sent_at.timestamp()
    if event.eviction_done_at:
        at["answered"] = event.eviction_done_at.timestamp()
    received = event.received_at.timestamp()
    event.response["stages"] = {k: round((at[k] - received) * 1000, 3) for k in STAGES if at.get(k) is not None}


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
        try:
            lifted += _lift(taint, now)
        except Exception:  # one taint the code cannot lift must not keep every other node tainted (issue 25)
            log.exception("lifting taint %s of node %s (cluster %s) failed; skipped until the next sweep",
                          taint.pk, taint.node_id, taint.cluster_id)  # fmt: skip
    return lifted


def _lift(taint: NodeTaint, now: datetime) -> int:
    """Lift one expired taint (in the API, then on the node's row) unless a later one with its key holds; 1 when
    it is done with, 0 when the API refused (tried again at the next sweep)."""
    still = NodeTaint.objects.filter(
        node=taint.node, key=taint.key, effect=taint.effect, lifted_at__isnull=True, expires_at__gt=now
    ).exists()
    if not still:
        if has_api(taint.cluster):
            try:
                kube_for(taint.cluster).set_taint(taint.node.name, taint.as_dict(), present=False)
            except KUBE_ERRORS as exc:
                NodeTaint.objects.filter(pk=taint.pk).update(error=problem(exc)[:500])
                return 0  # try again next time
        with transaction.atomic():
            node = ComputeNode.objects.select_for_update().get(pk=taint.node_id)
            kept = [t for t in node.taints if not (t.get("key") == taint.key and t.get("effect") == taint.effect)]
            if kept != node.taints:
                node.taints = kept
                node.save(update_fields=["taints"])
    NodeTaint.objects.filter(pk=taint.pk).update(lifted_at=now)
    return 1


def active_taints(cluster: Cluster) -> Q:
    return Q(cluster=cluster, lifted_at__isnull=True)
