"""What the verification API, jobs and pages do with the engine: route robots' events to the handlers'
Redis network or to in-process monitors, read the handlers' reports back, build the MILP's statistics from
the database, store allocation runs, migrations and simulations."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Mapping
from datetime import UTC, datetime
from typing import Any

from django.conf import settings
from django.db import transaction

from apps.clusters.models import Cluster, ComputeNode
from apps.jobs.registry import owned_row
from continuum.engine.core.errors import InputError
from continuum.engine.verification.abv_simulation import SimulationResult
from continuum.engine.verification.monitor_milp import DEFAULT_WORK_LIMIT, Allocation, MonitorStats, allocate
from continuum.engine.verification.stl_monitor import Monitor as EngineMonitor
from continuum.verification_runtime.coordinator import gone_handlers, hand_over

from .models import AllocationRun, Handler, MigrationEvent, Monitor, MonitorVerdict, Verdict, Violation

MAX_EVENTS = 10_000
DEFAULT_MONITOR_CPU = 0.5  # % of a node, for a monitor no handler has measured yet


# ---- events -----------------------------------------------------------------------------------------
def parse_events(raw: Any) -> list[tuple[str, Any, float]]:
    """Validate a batch: ``[[variable, value, timestamp_ms], ...]`` or ``[{"variable", "value", "timestamp"}]``.
    Any malformed event rejects the whole batch (InputError naming it)."""
    if not isinstance(raw, list) or not raw:
        raise InputError("events must be a non-empty list", "events")
    if len(raw) > MAX_EVENTS:
        raise InputError(f"at most {MAX_EVENTS} events per request, got {len(raw)}", "events")
    out = []
    for n, item in enumerate(raw):
        where = f"events[{n}]"
        if isinstance(item, Mapping):
            unknown = sorted(set(item) - {"variable", "value", "timestamp"})
            if unknown:
                raise InputError(f"{where}: unknown field {unknown[0]!r}", "events")
            try:
                var, value, ts = item["variable"], item["value"], item["timestamp"]
            except KeyError as exc:
                raise InputError(f"{where}: missing {exc.args[0]!r}", "events") from None
        elif isinstance(item, list) and len(item) == 3:
            var, value, ts = item
        else:
            raise InputError(f"{where}: expected [variable, value, timestamp] or an object", "events")
        if not isinstance(var, str) or not var.strip():
            raise InputError(f"{where}: variable must be a non-empty string", "events")
        if isinstance(value, float) and not math.isfinite(value):
            raise InputError(f"{where}: value must be finite", "events")
        if value is not None and not isinstance(value, (bool, int, float, str)):
            raise InputError(f"{where}: value must be a number, a boolean or a string", "events")
        if isinstance(ts, bool) or not isinstance(ts, (int, float)) or not math.isfinite(ts) or ts < 0:
            raise InputError(f"{where}: timestamp must be a finite number of milliseconds >= 0", "events")
        out.append((var.strip(), value, float(ts)))
    return out


def bus_for(cluster: Cluster):
    """The cluster's verification network (None when no Redis is configured)."""
    url = settings.CONTINUUM_VERIFICATION_REDIS_URL
    if not url:
        return None
    from continuum.verification_runtime.bus import Bus

    return Bus(url, prefix=f"{settings.CONTINUUM_VERIFICATION_PREFIX}:{cluster.pk}")


def live_reports(bus, reports: dict[str, dict] | None = None) -> dict[str, dict]:
    """Handlers that reported within the liveness window and are not shutting down."""
    horizon = settings.CONTINUUM_HANDLER_LIVENESS_S
    now = time.time()
    return {
        name: r
        for name, r in (bus.handlers() if reports is None else reports).items()
        if now - float(r.get("wall", 0)) <= horizon and not r.get("shutting_down")
    }


def route_events(cluster: Cluster, events: list[tuple[str, Any, float]], now: float | None = None) -> dict:
    """Publish the batch on the handlers' event stream when some handler of the cluster runs, else
    evaluate it here with the engine's monitors (their state is kept in the database)."""
    bus = bus_for(cluster)
    if bus is not None:
        try:
            live = live_reports(bus)
        except Exception:  # Redis unreachable: the handlers cannot be running either
            live = {}
        if live:
            _register(cluster, bus, live)
            bus.publish_events(events)
            return {"routed": "redis", "events": len(events), "handlers": sorted(live)}
    return evaluate_in_process(cluster, events, now)


def _register(cluster: Cluster, bus, live: Mapping[str, dict]) -> None:
    """Make sure the handlers know every monitor of the cluster; start unplaced ones on their node."""
    placed = bus.allocation()
    for m in cluster.monitors.select_related("assertion", "node"):
        bus.register_monitor(
            m.name, m.assertion.text, constants=m.assertion.constants, options={"tolerant": m.tolerant}
        )
        if m.name not in placed and m.node is not None and m.node.name in live:
            bus.send(m.node.name, "EXEC", monitors=[m.name])
            bus.set_allocation(m.name, m.node.name)


@transaction.atomic
def evaluate_in_process(cluster: Cluster, events: list[tuple[str, Any, float]], now: float | None = None) -> dict:
    monitors = list(Monitor.objects.select_for_update().filter(cluster=cluster).select_related("assertion"))
    found: list[dict] = []
    touched = 0
    for row in monitors:
        program = row.assertion.program()
        mine = [e for e in events if e[0] in program.deps]
        if not mine and now is None:
            continue
        touched += 1
        if row.state:
            engine = EngineMonitor.from_dict(row.state, program)
        else:
            engine = EngineMonitor(program, tolerant=row.tolerant)
        violations = engine.feed(mine)
        if now is not None:
            violations += engine.tick(now)
        for v in violations:
            _, created = Violation.objects.get_or_create(
                monitor=row,
                time_ms=v.time,
                instance_start_ms=v.instance_start,
                defaults={"event": list(v.event) if v.event else None, "handler": "in-process"},
            )
            if created:
                found.append({"monitor": row.name, **v.to_dict()})
        row.state = engine.to_dict()
        row.events += len(mine)
        row.violation_count = row.violations.count()
        row.active_instances = engine.active_instances
        row.verdict = Verdict.FAIL if row.violation_count else Verdict.PENDING
        row.save(update_fields=["state", "events", "violation_count", "active_instances", "verdict", "updated"])
    return {"routed": "in-process", "events": len(events), "monitors": touched, "violations": found}


@transaction.atomic
def finish_in_process(monitor: Monitor) -> MonitorVerdict:
    """Close the monitor's stream: evaluate what is buffered and record its verdict (pending instances make
    it inconclusive), then start afresh."""
    monitor = Monitor.objects.select_for_update().select_related("assertion").get(pk=monitor.pk)
    program = monitor.assertion.program()
    engine = (
        EngineMonitor.from_dict(monitor.state, program)
        if monitor.state
        else EngineMonitor(program, tolerant=monitor.tolerant)
    )
    for v in engine.flush():
        Violation.objects.get_or_create(
            monitor=monitor,
            time_ms=v.time,
            instance_start_ms=v.instance_start,
            defaults={"event": list(v.event) if v.event else None, "handler": "in-process"},
        )
    verdict = engine.verdict()
    row = MonitorVerdict.objects.create(
        monitor=monitor,
        verdict=verdict,
        counters=engine.counters,
        pending=engine.pending_starts(),
        handler="in-process",
    )
    monitor.verdict = verdict
    monitor.violation_count = monitor.violations.count()
    monitor.state = None
    monitor.active_instances = 0
    monitor.save(update_fields=["verdict", "violation_count", "state", "active_instances", "updated"])
    return row


# ---- handlers ----------------------------------------------------------------------------------------
def ensure_handlers(cluster: Cluster) -> list[Handler]:
    """One handler row per compute node of the cluster."""
    for node in cluster.nodes.all():
        Handler.objects.get_or_create(node=node, defaults={"cluster": cluster})
    return list(Handler.objects.filter(cluster=cluster).select_related("node"))


def sync_handlers(cluster: Cluster) -> dict:
    """Read the handlers' reports, the coordinator and the verdicts from the cluster's Redis network."""
    handlers = {h.node.name: h for h in ensure_handlers(cluster)}
    bus = bus_for(cluster)
    if bus is None:
        return {"handlers": len(handlers), "redis": False, "violations": 0, "verdicts": 0}
    reports = bus.handlers()
    coordinator = bus.coordinator()
    for name, h in handlers.items():
        report = reports.get(name)
        h.is_coordinator = coordinator == name
        if report:
            h.last_seen = datetime.fromtimestamp(float(report.get("wall", 0)), tz=UTC)
            h.free_cpu = report.get("free_cpu")
            h.verification_cpu = report.get("verification_cpu")
            h.monitor_cpu = report.get("monitor_cpu", {})
            h.active = report.get("active", [])
            h.delay_ms = report.get("delay_ms", h.delay_ms)
            h.threshold = report.get("threshold", h.threshold)
        h.save()
    monitors = {m.name: m for m in cluster.monitors.all()}
    nodes = {n.name: n for n in cluster.nodes.all()}
    for name, where in bus.allocation().items():
        m = monitors.get(name)
        if m is not None and where in nodes and m.node_id != nodes[where].pk:
            m.node = nodes[where]
            m.save(update_fields=["node", "updated"])
    _record_handovers(cluster, bus.acks())
    violations = verdicts = 0
    for entry in bus.verdicts():
        m = monitors.get(entry["monitor"])
        if m is None:
            continue
        body = entry["body"]
        if entry["kind"] == "violation":
            _, created = Violation.objects.get_or_create(
                monitor=m,
                time_ms=body["time"],
                instance_start_ms=body["instance_start"],
                defaults={"event": body.get("event"), "handler": entry.get("handler", "")},
            )
            violations += created
        elif (
            entry["kind"] == "final"
            and not m.verdicts.filter(handler=entry.get("handler", ""), counters=body.get("counters", {})).exists()
        ):
            MonitorVerdict.objects.create(
                monitor=m,
                verdict=body["verdict"],
                counters=body.get("counters", {}),
                pending=body.get("pending", []),
                handler=entry.get("handler", ""),
            )
            verdicts += 1
            m.verdict = body["verdict"]
        m.violation_count = m.violations.count()
        if m.violation_count:
            m.verdict = Verdict.FAIL
        m.save(update_fields=["violation_count", "verdict", "updated"])
    return {"handlers": len(handlers), "redis": True, "violations": violations, "verdicts": verdicts}


def _record_handovers(cluster: Cluster, acks: list[tuple[str, dict]]) -> None:
    """Fill ``events_moved`` of the cluster's migrations from the handlers' "migrated" acknowledgements
    (the instants the source handed over, Fig. 3.43 step 5): the k-th acknowledgement of a move (monitor,
    from, to) belongs to the k-th such migration recorded, so a repeated sync changes nothing."""
    moves: dict[tuple[str, str, str], list[int]] = {}
    for kind, body in acks:
        if kind == "migrated" and "moved" in body:
            key = (body["monitor"], body.get("source", ""), body.get("handler", ""))
            moves.setdefault(key, []).append(int(body["moved"]))
    for (monitor, source, target), counts in moves.items():
        rows = MigrationEvent.objects.filter(
            run__cluster=cluster, monitor_name=monitor, source=source, target=target
        ).order_by("created", "pk")
        for row, moved in zip(rows, counts, strict=False):
            if row.events_moved != moved:
                row.events_moved = moved
                row.save(update_fields=["events_moved"])


# ---- allocation ------------------------------------------------------------------------------------------
def stats_document(cluster: Cluster) -> dict:
    """The MILP's input (``continuum.monitorstats/v1``) from the cluster's handlers and monitors: nodes with
    their handler's threshold and last free CPU (100 % when never reported), each monitor's measured CPU
    where it runs (DEFAULT_MONITOR_CPU when unmeasured), topics = the assertions' signals with the
    receiving handler's delay."""
    handlers = ensure_handlers(cluster)
    if not handlers:
        raise InputError(f"cluster {cluster.name!r} has no node", "cluster")
    monitors = list(cluster.monitors.select_related("assertion", "node"))
    if not monitors:
        raise InputError(f"cluster {cluster.name!r} has no monitor to place", "cluster")
    nodes = []
    for h in handlers:
        free = 100.0 if h.free_cpu is None else h.free_cpu
        nodes.append(
            {
                "name": h.node.name,
                "available_cpu": max(0.0, min(100.0, free + (h.verification_cpu or 0.0))),
                "threshold": h.threshold,
                "speed": h.node.speed,
            }
        )
    variables = {m.name: m.assertion.variables for m in monitors}
    topics = sorted({v for vs in variables.values() for v in vs})
    topic_docs = [
        {
            "name": t,
            "delay": {h.node.name: h.delay_ms for h in handlers},
            "cpu": {h.node.name: 0.0 for h in handlers},
        }
        for t in topics
    ]
    monitor_docs = []
    for m in monitors:
        cpu = {n: float(v) for n, v in (m.cpu or {}).items() if any(h.node.name == n for h in handlers)}
        for h in handlers:
            if m.name in (h.monitor_cpu or {}):
                cpu[h.node.name] = float(h.monitor_cpu[m.name])
        if not cpu:
            cpu = {(m.node.name if m.node else handlers[0].node.name): DEFAULT_MONITOR_CPU}
        monitor_docs.append(
            {
                "name": m.name,
                "topics": variables[m.name],
                "cpu": cpu,
                "current": m.node.name if m.node else None,
                "tolerant": m.tolerant,
                "active_instances": m.active_instances,
            }
        )
    return {"format": "continuum.monitorstats/v1", "nodes": nodes, "topics": topic_docs, "monitors": monitor_docs}


def store_allocation(
    fleet, stats: MonitorStats, result: Allocation, *, cluster: Cluster | None = None, job=None, raw: dict | None = None
) -> AllocationRun:
    run = AllocationRun.objects.create(
        fleet=fleet,
        cluster=cluster,
        job=job,
        source=AllocationRun.Source.API,
        stats=raw,
        n_monitors=len(stats.monitors),
        n_nodes=len(stats.nodes),
        n_topics=len(stats.topics),
        status=result.status,
        feasible=result.feasible,
        objective=result.objective,
        solve_time_ms=result.solve_time_ms,
        result=result.to_dict(),
        nodes={
            j: {
                "cpu": result.cpu[j],
                "capacity": result.capacity[j],
                "threshold": stats.threshold[j],
                "monitors": sum(1 for v in result.allocation.values() if v == j),
            }
            for j in stats.nodes
        },
    )
    by_name = {m.name: m for m in cluster.monitors.all()} if cluster is not None else {}
    MigrationEvent.objects.bulk_create(
        MigrationEvent(
            fleet=fleet,
            run=run,
            monitor=by_name.get(i),
            monitor_name=i,
            source=stats.current[i],
            target=result.allocation[i],
        )
        for i in result.migrations
    )
    return run


def solve_budget(args: Mapping[str, Any]) -> dict[str, Any]:
    """The solver's budget from a job's arguments: ``work_limit`` branch-and-bound nodes per solve (default
    :data:`~continuum.engine.verification.monitor_milp.DEFAULT_WORK_LIMIT`), so that the same statistics give
    the same allocation whatever the machine's load (a 10 s wall-clock budget stopped every large solve with a
    100 % gap on a loaded machine). ``time_limit`` (seconds) only when the request gives one: a cap that makes
    the result depend on the load again, for who wants an answer by a deadline. Without one, the solve still
    stops at ``CONTINUUM_MILP_SAFETY_CAP_S`` (a safety net below the job's time limit: the node budget does
    not bound HiGHS' root work, and cross-robot fleets of 1000 x 20 were seen to run for minutes on it)."""
    work = args.get("work_limit")
    seconds = args.get("time_limit")
    return {
        "work_limit": int(work) if work is not None else DEFAULT_WORK_LIMIT,
        "time_limit": float(seconds) if seconds is not None else settings.CONTINUUM_MILP_SAFETY_CAP_S,
    }


def run_allocation(job, progress: Callable[[float, str], None]) -> AllocationRun:
    """The ``allocate_monitors`` job: solve, store, and (``apply``) move the monitors."""
    args = job.arguments or {}
    cluster = owned_row(job, Cluster.objects, "cluster", required=False)
    run = AllocationRun.objects.filter(job=job).first()
    if run is not None:  # re-delivered: the solve is stored already
        return run
    progress(5, "reading statistics")
    raw = args.get("stats") if args.get("stats") is not None else stats_document(cluster)
    stats = MonitorStats.from_dict(raw)
    progress(20, f"solving the MILP: {len(stats.monitors)} monitors on {len(stats.nodes)} nodes")
    result = allocate(stats, **solve_budget(args))
    progress(80, f"{result.status}: {len(result.migrations)} migration(s), {result.solve_time_ms:.1f} ms")
    with transaction.atomic():
        run = store_allocation(job.fleet, stats, result, cluster=cluster, job=job, raw=raw)
        if args.get("apply") and cluster is not None:
            apply_allocation(run, cluster)
    return run


def apply_allocation(run: AllocationRun, cluster: Cluster) -> None:
    """Record the new nodes; on a live network, ask the handlers to migrate (Fig. 3.43) or start them."""
    nodes = {n.name: n for n in cluster.nodes.all()}
    allocation = run.result["allocation"]
    for m in cluster.monitors.all():
        target = nodes.get(allocation.get(m.name))
        if target is not None and m.node_id != target.pk:
            m.node = target
            m.save(update_fields=["node", "updated"])
    bus = bus_for(cluster)
    if bus is not None:
        # The coordinator's rule: a late handler keeps its monitors; only a gone one's start afresh.
        reports = bus.handlers()
        gone = gone_handlers(reports, settings.CONTINUUM_HANDLER_GONE_AFTER_S)
        hand_over(bus, allocation, live_reports(bus, reports), gone)
    run.applied = True
    run.save(update_fields=["applied"])


# ---- simulations -----------------------------------------------------------------------------------------
def store_simulation(fleet, result: SimulationResult, job=None) -> tuple[Any, list[AllocationRun]]:
    """One AllocationRun per simulated period (series = one UUID) and one MigrationEvent per move."""
    series = AllocationRun.new_series()
    runs = []
    for p in result.periods:
        a = p.allocation or {}
        runs.append(
            AllocationRun(
                fleet=fleet,
                job=job,
                source=AllocationRun.Source.SIMULATION,
                scenario=result.scenario,
                series=series,
                t=p.t,
                n_monitors=sum(p.monitors.values()),
                n_nodes=len(result.nodes),
                status=a.get("status", ""),
                feasible=a.get("feasible", True),
                objective=a.get("objective"),
                solve_time_ms=a.get("solve_time_ms"),
                result=a or None,
                makespan_ms=p.makespan_ms,
                nodes={
                    j: {
                        "cpu": p.cpu[j],
                        "background": p.background[j],
                        "verification": p.verification[j],
                        "monitors": p.monitors[j],
                        "dropped": p.dropped[j],
                        "threshold": result.thresholds[j],
                    }
                    for j in result.nodes
                },
            )
        )
    runs = AllocationRun.objects.bulk_create(runs)
    by_t = {r.t: r for r in runs}
    MigrationEvent.objects.bulk_create(
        MigrationEvent(
            fleet=fleet,
            run=by_t[m.t],
            monitor_name=m.monitor,
            source=m.source,
            target=m.target,
            t=m.t,
            events_moved=m.events_moved,
        )
        for m in result.migrations
    )
    last = runs[-1]
    last.result = {
        **(last.result or {}),
        "summary": result.summary(),
        "violations": result.violations,
        "legs": result.legs,
        "placement": result.placement,
    }
    last.save(update_fields=["result"])
    return series, runs


def nodes_of(cluster: Cluster) -> Iterable[ComputeNode]:
    return cluster.nodes.order_by("name")
