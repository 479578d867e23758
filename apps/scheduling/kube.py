"""Pushing a stored schedule to its cluster's Kubernetes API: one pod per assignment, bound to its node.

The gateway (:mod:`apps.kube.pods`) places the pods of engine assignments and reports an Outcome for each;
this module owns the Schedule and Assignment rows: it orders the assignments (highest upward rank first,
spec 02 §7.3), keeps the pod name of a task a remap kept, records ``placement``/``placement_message``/
``pod_name`` on every assignment and registers the ``push_schedule`` job.
"""

from __future__ import annotations

from django.conf import settings
from django.db import transaction

from apps.clusters.kube import api_client_for
from apps.jobs.registry import job_kind, owned_row
from apps.kube import gateway
from apps.kube.gateway import KubeError, Outcome, PodSet, Progress
from apps.scheduling.kinds import SchedulingJob

from .models import Assignment, Schedule


def pod_set(schedule: Schedule) -> PodSet:
    """Whose pods these are, for the gateway: ids, the application's name, the ranks and the namespace."""
    cluster = schedule.cluster
    namespace = (cluster.namespace if cluster is not None else "") or settings.CONTINUUM_DEFAULT_NAMESPACE
    return PodSet(
        schedule=schedule.pk,
        application=schedule.application_id,
        application_name=schedule.application.name,
        namespace=namespace,
        ranks=dict(schedule.ranks or {}),
    )


def pod_name(schedule: Schedule, task: str, frame: int) -> str:
    """The name of a task's pod in ``schedule`` (see :func:`apps.kube.pods.pod_name`)."""
    return gateway.pod_name(pod_set(schedule), task, frame)


def pod_manifest(schedule: Schedule, assignment: Assignment, name: str):
    """The pod of one stored assignment (see :func:`apps.kube.pods.pod_manifest`)."""
    return gateway.pod_manifest(pod_set(schedule), assignment.to_engine(), name)


def pusher_for(schedule: Schedule, api_client) -> gateway.Pusher:
    """The gateway's pusher for ``schedule``'s pods."""
    return gateway.Pusher(pod_set(schedule), api_client)


def push_schedule(schedule: Schedule, progress: Progress | None = None) -> dict:
    """One pod per assignment in ``cluster.namespace``, bound to the assigned node; returns a summary.

    Records ``placement`` (bound/failed), ``placement_message`` and ``pod_name`` on every assignment.
    Raises :class:`KubeError` with a summary if any placement failed (the rows are stored first).
    """
    cluster = schedule.cluster
    if cluster is None:
        raise KubeError(f"schedule {schedule.pk} was computed on a platform document, not on a cluster")
    api_client = api_client_for(cluster)
    pods = pod_set(schedule)
    ranks = schedule.ranks or {}
    # Highest upward rank first (spec 02 §7.3); ties by start time, then task id, for a stable order.
    assignments = sorted(schedule.assignments.all(), key=lambda a: (-ranks.get(a.task, 0.0), a.start, a.task, a.frame))
    # A task kept by a remap (apps.heft4k) still runs in the pod of the earlier schedule: keep its name.
    names = {a.pk: a.pod_name or gateway.pod_name(pods, a.task, a.frame) for a in assignments}
    with api_client:
        results, fatal = gateway.push(pods, api_client, [(a.to_engine(), names[a.pk]) for a in assignments], progress)
    outcomes: dict[int, Outcome] = {a.pk: outcome for a, outcome in zip(assignments, results, strict=True)}
    changed = []
    for assignment in assignments:
        outcome = outcomes[assignment.pk]
        before = (assignment.placement, assignment.placement_message, assignment.pod_name)
        assignment.placement = Assignment.Placement.BOUND if outcome.ok else Assignment.Placement.FAILED
        assignment.placement_message = outcome.message[:500]
        assignment.pod_name = names[assignment.pk]
        if before != (assignment.placement, assignment.placement_message, assignment.pod_name):
            changed.append(assignment)
    if changed:  # a re-push that changes nothing writes nothing
        with transaction.atomic():
            Assignment.store_placements(changed)
    failed = [a for a in assignments if not outcomes[a.pk].ok]
    summary = {
        "schedule": schedule.pk,
        "namespace": pods.namespace,
        "pods": len(assignments),
        "bound": len(assignments) - len(failed),
        "failed": len(failed),
    }
    if failed:
        raise KubeError(_failure_summary(schedule, cluster, failed, len(assignments), fatal))
    return summary


def _failure_summary(schedule, cluster, failed: list[Assignment], total: int, fatal: str | None) -> str:
    if fatal:
        return f"push of schedule {schedule.pk} to cluster {cluster.name!r} failed: {fatal}"
    reasons: dict[str, list[str]] = {}
    for a in failed:
        reasons.setdefault(a.placement_message, []).append(a.task if a.frame == 0 else f"{a.task}#{a.frame}")
    parts = []
    for reason, tasks in sorted(reasons.items(), key=lambda kv: -len(kv[1])):
        shown = ", ".join(tasks[:5]) + (f" and {len(tasks) - 5} more" if len(tasks) > 5 else "")
        parts.append(f"{reason} (tasks {shown})")
    return f"{len(failed)} of {total} placements of schedule {schedule.pk} failed: " + "; ".join(parts)


@job_kind(SchedulingJob.PUSH_SCHEDULE)
def push_schedule_job(job, progress) -> tuple[dict, str]:
    """Arguments: ``schedule`` (id). Creates one pod per assignment and binds it to the assigned node."""
    schedule = owned_row(job, Schedule.objects.select_related("cluster", "application"), "schedule")
    progress(1, f"pushing schedule {schedule.pk} to {schedule.cluster or 'no cluster'}")
    summary = push_schedule(schedule, progress)
    return summary, f"/api/v1/schedules/{schedule.pk}/"
