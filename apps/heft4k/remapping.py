"""HEFT4K remapping as a product (thesis 3.3.2, Algorithm 2): compute, store and apply a remap of a schedule.

:func:`compute` runs the engine's :func:`continuum.engine.heft4k.remap.remap` on a stored schedule and stores the
result as a new Schedule row plus a :class:`RemapEvent`; nothing touches Kubernetes. :func:`apply` pushes
ONLY the pods that change (a task moved to another node, or given another niceness by a total remap): the
old pod is deleted and a new one created and bound to the new node; every other pod is left untouched and
the new schedule records it as its own (same pod name). The nodes treated as failed are the ones asked for
plus, on a cluster, every node of the schedule that the cluster no longer reports Ready, so a remap never
targets a node known to be down. A pod on a node that is not Ready in the Kubernetes API is deleted with
grace period 0 (no kubelet will confirm a graceful deletion), any other one gracefully.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable

from django.conf import settings
from django.db import transaction
from django.utils import timezone

from apps.clusters.kube import api_client_for
from apps.clusters.models import ComputeNode
from apps.kube import gateway
from apps.scheduling.kube import pod_name, pusher_for
from apps.scheduling.models import Assignment, Schedule
from continuum.engine.core.errors import InputError
from continuum.engine.heft4k.remap import remap

from .models import RemapEvent

Progress = Callable[[float, str], None]
#: Schedule parameters of a HEFT4K plan that the remap keeps (same niceness range and mapping rule).
KEPT_PARAMS = ("nice_high", "nice_low", "rounding")


# ---- checks -------------------------------------------------------------------------------------------
def schedule_nodes(schedule: Schedule) -> list[str]:
    """The nodes (processors) the schedule was made on, in platform order."""
    return [str(p["id"]) for p in schedule.platform.get("processors", [])]


def failed_nodes(schedule: Schedule, requested: Iterable[str]) -> list[str]:
    """``requested`` (checked against the schedule's nodes) plus the schedule's nodes that are down now."""
    requested = list(dict.fromkeys(requested))
    nodes = schedule_nodes(schedule)
    if not requested:
        raise InputError("name at least one node to fail", "fail")
    for name in requested:
        if not isinstance(name, str) or name not in nodes:
            raise InputError(f"unknown node {name!r}: schedule {schedule.pk} was made on {', '.join(nodes)}", "fail")
    down: list[str] = []
    if schedule.cluster_id is not None:
        status = dict(ComputeNode.objects.filter(cluster_id=schedule.cluster_id).values_list("name", "status"))
        # A node deleted from the cluster is as gone as a NotReady one.
        down = [n for n in nodes if status.get(n) != ComputeNode.Status.READY]
    failed = list(dict.fromkeys([*requested, *down]))
    if len(failed) >= len(nodes):
        raise InputError(f"no node of schedule {schedule.pk} would be left: {', '.join(failed)} all fail", "fail")
    return failed


def check(schedule: Schedule, requested: Iterable[str], threshold: float | None = None) -> list[str]:
    """Everything that would make a remap of ``schedule`` fail, as InputError; returns the failed nodes."""
    if threshold is not None and not 0.0 <= threshold <= 1.0:
        raise InputError(f"threshold must be a fraction in [0, 1], not {threshold!r}", "threshold")
    if schedule.assignments.filter(frame__gt=0).exists():
        raise InputError(
            f"schedule {schedule.pk} has several frames; remapping works on single-frame DAG schedules", "schedule"
        )
    failed = failed_nodes(schedule, requested)
    if not schedule.assignments.filter(processor__in=failed).exists():
        raise InputError(f"no task of schedule {schedule.pk} runs on {', '.join(failed)}: nothing to remap", "fail")
    return failed


def superseded_by(event: RemapEvent) -> RemapEvent | None:
    """Another remap of the same schedule that was (or is being) applied in Kubernetes."""
    return (
        RemapEvent.objects.filter(
            schedule_id=event.schedule_id, status__in=[RemapEvent.Status.APPLIED, RemapEvent.Status.APPLYING]
        )
        .exclude(pk=event.pk)
        .first()
    )


def cannot_apply(event: RemapEvent) -> str:
    """Why ``event`` cannot be applied ("" when it can)."""
    # "applying" again is the same job delivered again (or a retry): applying is idempotent.
    if event.status not in (RemapEvent.Status.WHAT_IF, RemapEvent.Status.FAILED, RemapEvent.Status.APPLYING):
        return f"remap {event.pk} is already {event.get_status_display()}"
    if event.new_schedule_id is None:
        return f"the schedule remap {event.pk} produced was deleted"
    other = superseded_by(event)
    if other is not None:
        return (
            f"schedule {event.schedule_id} was already remapped by remap {other.pk}; "
            f"compute a new what-if on schedule {other.new_schedule_id}"
        )
    return ""


def latest_pushed(application_id: int, cluster) -> Schedule | None:
    """The newest schedule of an application on ``cluster`` that has pods in Kubernetes."""
    return (
        Schedule.objects.filter(
            application_id=application_id, cluster=cluster, assignments__placement=Assignment.Placement.BOUND
        )
        .distinct()
        .order_by("-created", "-pk")
        .first()
    )


# ---- compute ------------------------------------------------------------------------------------------
def compute(
    schedule: Schedule,
    requested: Iterable[str],
    *,
    threshold: float | None = None,
    trigger: str = RemapEvent.Trigger.API,
    job=None,
) -> RemapEvent:
    """Run Algorithm 2 on ``schedule`` and store the new schedule and the event (nothing is pushed)."""
    threshold = settings.CONTINUUM_REMAP_THRESHOLD if threshold is None else threshold
    failed = check(schedule, requested, threshold)
    dag = schedule.application.graph
    platform = schedule.engine_platform()
    old = schedule.to_engine()
    params = {k: schedule.params[k] for k in KEPT_PARAMS if k in schedule.params}
    result = remap(
        old, dag, platform, failed, threshold=threshold, lookahead=schedule.params.get("lookahead", True), **params
    )
    before = {a.task: a.niceness for a in old.assignments}
    after = {a.task: a.niceness for a in result.schedule.assignments}
    moved = set(result.moved)
    reniced = [t for t in dag.tasks if t not in moved and after[t] != before.get(t)]
    with transaction.atomic():
        new = Schedule.store(
            result.schedule,
            application=schedule.application,
            platform=platform.without(result.failed),
            cluster=schedule.cluster,
            job=job,
        )
        event = RemapEvent.objects.create(
            fleet_id=schedule.fleet_id,
            application_id=schedule.application_id,
            schedule=schedule,
            new_schedule=new,
            job=job,
            trigger=trigger,
            decision=result.mode,
            reason=result.reason[:300],
            failed_nodes=result.failed,
            lost_tasks=result.lost,
            moved_tasks=result.moved,
            reniced_tasks=reniced,
            critical_lost=result.critical_lost,
            lost_share=result.lost_share,
            threshold=result.threshold,
            makespan_before=result.makespan_before,
            makespan_after=result.makespan_after,
            elapsed_ms=result.elapsed_ms,
        )
    return event


def summary(event: RemapEvent) -> dict:
    """What a remap job reports as its result."""
    return {
        "remap": event.pk,
        "schedule": event.new_schedule_id,
        "from_schedule": event.schedule_id,
        "decision": event.decision,
        "status": event.status,
        "failed": event.failed_nodes,
        "lost": event.lost_tasks,
        "moved": event.moved_tasks,
        "reniced": event.reniced_tasks,
        "makespan_before": event.makespan_before,
        "makespan_after": event.makespan_after,
        "elapsed_ms": event.elapsed_ms,
        "pods_moved": event.pods_moved,
    }


# ---- apply --------------------------------------------------------------------------------------------
def apply(event: RemapEvent, progress: Progress | None = None) -> dict:
    """Make Kubernetes follow ``event.new_schedule``, touching only the pods of the changed tasks.

    Idempotent: a re-run deletes what is already deleted (404 is fine) and finds the new pods created and
    bound. Raises :class:`~apps.kube.gateway.KubeError` after recording when a pod could not be placed.
    """
    progress = progress or (lambda percent, message: None)
    if event.status == RemapEvent.Status.APPLIED:
        return summary(event)
    with transaction.atomic():
        # One remap of a schedule may be applied, never two (two watchers, a watcher and an operator...).
        Schedule.objects.select_for_update().filter(pk=event.schedule_id).first()
        event.refresh_from_db()
        reason = cannot_apply(event)
        if reason:
            raise ValueError(reason)
        event.status = RemapEvent.Status.APPLYING
        event.save(update_fields=["status"])
    old, new = event.schedule, event.new_schedule
    old_rows = {(a.task, a.frame): a for a in old.assignments.all()}
    new_rows = {(a.task, a.frame): a for a in new.assignments.all()}
    cluster = old.cluster
    pushed = any(a.placement == Assignment.Placement.BOUND for a in old_rows.values())
    if cluster is None or not cluster.kubeconfig.strip() or not pushed:
        why = (
            "the cluster has no Kubernetes API"
            if cluster is None or not cluster.kubeconfig.strip()
            else f"schedule {old.pk} was never pushed"
        )
        _finish(event, RemapEvent.Status.NOT_PUSHED, f"stored; {why}, so no pod was changed", [], None)
        return summary(event)

    changed = set(event.changed_tasks)
    for key, row in new_rows.items():
        if key[0] not in changed:  # the pod of the earlier schedule keeps running: it is this schedule's now
            before = old_rows[key]
            row.placement, row.placement_message, row.pod_name = (
                before.placement,
                before.placement_message,
                before.pod_name,
            )
    ranks = new.ranks or {}
    order = sorted((k for k in new_rows if k[0] in changed), key=lambda k: (-ranks.get(k[0], 0.0), k))
    began = time.perf_counter()
    pods, fatal = _replace_pods(event, old, new, old_rows, new_rows, order, progress)
    push_ms = (time.perf_counter() - began) * 1000.0
    failed = [p for p in pods if not p["ok"]]
    with transaction.atomic():
        Assignment.objects.bulk_update(new_rows.values(), ["placement", "placement_message", "pod_name"])
        deleted = {p["task"] for p in pods if p["deleted"]}
        gone = [old_rows[k] for k in order if k[0] in deleted]
        for row in gone:
            row.placement = Assignment.Placement.NOT_PUSHED
            row.placement_message = f"pod deleted by remap {event.pk}: the task runs in schedule {new.pk}"[:500]
        Assignment.objects.bulk_update(gone, ["placement", "placement_message"])
        if failed:
            message = fatal or f"{len(failed)} of {len(pods)} pods could not be placed: " + "; ".join(
                f"{p['task']}: {p['message']}" for p in failed[:5]
            )
            _finish(event, RemapEvent.Status.FAILED, message, pods, push_ms)
        else:
            message = f"{len(pods)} pods recreated, {len(new_rows) - len(pods)} kept"
            _finish(event, RemapEvent.Status.APPLIED, message, pods, push_ms)
    progress(100, event.message)
    if failed:
        raise gateway.KubeError(f"remap {event.pk}: {event.message}")
    return summary(event)


def _replace_pods(event, old, new, old_rows, new_rows, order, progress) -> tuple[list[dict], str]:
    """Delete the old pod and create + bind the new one for every changed task; one record per task.

    Returns the records and, when the API could not be used at all, why (every task not done fails)."""
    pods: list[dict] = []
    try:
        api_client = api_client_for(old.cluster)
    except gateway.KubeError as exc:
        return _fail_rest(pods, order, old_rows, new_rows, str(exc)), str(exc)
    with api_client:
        pusher = pusher_for(new, api_client)
        try:
            pusher.ensure_namespace()
            problems = pusher.node_problems()
            existing = pusher.existing_pods()
            # Only a Ready node's kubelet can stop a pod gracefully; elsewhere the pod object is removed at once.
            ready = pusher.ready_nodes()
            for i, key in enumerate(order, 1):
                before, row = old_rows[key], new_rows[key]
                old_name = before.pod_name or pod_name(old, *key)
                record = {
                    "task": key[0],
                    "from": before.processor,
                    "to": row.processor,
                    "niceness_before": before.niceness,
                    "niceness_after": row.niceness,
                    "old_pod": old_name,
                    "deleted": pusher.delete(old_name, force=before.processor not in ready),
                }
                name = pod_name(new, *key)
                outcome = pusher.place(row.to_engine(), name, existing.get(name), problems)
                row.placement = Assignment.Placement.BOUND if outcome.ok else Assignment.Placement.FAILED
                row.placement_message, row.pod_name = outcome.message[:500], name
                record.update(new_pod=name, created=outcome.ok, ok=outcome.ok, message=outcome.message)
                pods.append(record)
                progress(50 + 45 * i / max(len(order), 1), f"recreated {i}/{len(order)} pods")
        except gateway.API_ERRORS as exc:
            fatal = gateway.describe(exc, pusher.server)
            return _fail_rest(pods, order, old_rows, new_rows, fatal), fatal
    return pods, ""


def _fail_rest(pods: list[dict], order, old_rows, new_rows, reason: str) -> list[dict]:
    """Record every changed task not handled yet as failed for ``reason``."""
    done = {p["task"] for p in pods}
    for key in order:
        if key[0] in done:
            continue
        row = new_rows[key]
        row.placement, row.placement_message = Assignment.Placement.FAILED, reason[:500]
        pods.append(
            {"task": key[0], "from": old_rows[key].processor, "to": row.processor, "deleted": False,
             "created": False, "ok": False, "message": reason}
        )  # fmt: skip
    return pods


def _finish(event: RemapEvent, status: str, message: str, pods: list[dict], push_ms: float | None) -> None:
    event.status = status
    event.message = message[:500]
    event.pods = pods
    event.push_ms = push_ms
    event.applied = timezone.now()
    event.save(update_fields=["status", "message", "pods", "push_ms", "applied"])
