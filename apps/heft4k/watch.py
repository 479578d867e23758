"""The node watcher: HEFT4K's event-driven remapping trigger (thesis 3.3.2, Algorithm 2).

:func:`watch_nodes` lists the Node objects of a cluster's Kubernetes API, then follows a watch stream from
that resourceVersion. A node that goes NotReady (or Unknown) or disappears is marked on its ComputeNode and
a ``remap`` job starts for the latest pushed schedule of every application that has tasks on a down node.

Robustness: the watch is re-opened when the server ends it (``timeout_seconds``), re-listed when the
resourceVersion expired (410 Gone) or after a lost connection, and a list is reconciled with the database
(level-triggered), so a failure that happened while the watcher was away is still handled. Consecutive
connection failures are retried with exponential backoff up to ``retries`` times, then
:class:`~apps.kube.gateway.KubeError` is raised. Each schedule gets at most one watcher-triggered remap job
(a failed one is left for the operator to look at, never retried in a loop). ``timeout`` bounds the whole
run (tests, cron); ``None`` watches until interrupted.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from apps.clusters.kube import api_client_for
from apps.clusters.models import Cluster, ComputeNode
from apps.clusters.nodes import NodeChange, record_node_status, status_of
from apps.heft4k.kinds import Heft4kJob
from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.kube import gateway
from apps.scheduling.models import Schedule

from . import remapping
from .models import RemapEvent

log = logging.getLogger(__name__)
#: Longest single watch request (seconds); the server ends it and the watcher re-opens it.
WATCH_SECONDS = gateway.WATCH_SECONDS


@dataclass
class WatchReport:
    """What one run of the watcher saw and did."""

    cluster: int
    events: int = 0
    lists: int = 0
    reconnects: int = 0
    changes: list[dict[str, Any]] = field(default_factory=list)  # {node, status, was}
    remaps: list[dict[str, Any]] = field(default_factory=list)  # {job, schedule, fail, state, remap}

    def to_dict(self) -> dict[str, Any]:
        return {
            "cluster": self.cluster,
            "events": self.events,
            "lists": self.lists,
            "reconnects": self.reconnects,
            "changes": self.changes,
            "remaps": self.remaps,
        }


def watch_nodes(
    cluster: Cluster,
    *,
    timeout: float | None = None,
    threshold: float | None = None,
    retries: int = 5,
    backoff: float = 1.0,
    on_listed: Callable[[WatchReport], None] | None = None,
    sleep: Callable[[float], None] = time.sleep,
) -> WatchReport:
    """Watch ``cluster``'s nodes for ``timeout`` seconds (forever when ``None``); see the module docstring.

    ``on_listed(report)`` is called after every list, once the database is reconciled and before the watch
    opens (changes made then arrive as watch events).
    """
    report = WatchReport(cluster.pk)
    stats = gateway.WatchStats()

    def listed(items: list[dict]) -> None:
        report.lists, report.reconnects = stats.lists, stats.reconnects
        _reconcile(cluster, {gateway.name_of(n): status_of(n) for n in items}, report)
        _trigger(cluster, threshold, report)
        if on_listed is not None:
            on_listed(report)

    def changed(event: dict) -> None:
        report.events = stats.events
        node = event["raw_object"]
        status = status_of(None if event["type"] == "DELETED" else node)
        if _mark(cluster, gateway.name_of(node), status, report):
            _trigger(cluster, threshold, report)

    try:
        gateway.follow(
            lambda: api_client_for(cluster),
            gateway.watch_nodes(),
            changed,
            on_list=listed,
            timeout=timeout,
            retries=retries,
            backoff=backoff,
            sleep=sleep,
            watch_seconds=WATCH_SECONDS,
            what="node watch",
            stats=stats,
        )
    finally:
        report.events, report.lists, report.reconnects = stats.events, stats.lists, stats.reconnects
    return report


def _reconcile(cluster: Cluster, statuses: dict[str, str], report: WatchReport) -> None:
    """Bring every ComputeNode's status to what the API says; a node missing from the API is NotReady."""
    for name in cluster.nodes.values_list("name", flat=True):
        _mark(cluster, name, statuses.get(name, status_of(None)), report)


def _mark(cluster: Cluster, name: str, status: str, report: WatchReport) -> bool:
    """Store a node's status (the one writer, :func:`apps.clusters.nodes.record_node_status`); True when a known
    node is now not Ready."""
    change = record_node_status(cluster, name, status)
    if change is None:
        return False  # a node Continuum does not know yet (kube_sync adds it), or nothing new
    report.changes.append(change.to_dict())
    return status != ComputeNode.Status.READY


def remap_trigger(cluster: Cluster, changes: list[NodeChange], listed: bool) -> None:
    """The cluster agent's node handler: after a list (level-triggered) or when a node left Ready, start the
    remap jobs :func:`_trigger` finds due (at most one watcher remap per schedule)."""
    if listed or any(c.status != ComputeNode.Status.READY for c in changes):
        report = WatchReport(cluster.pk)
        _trigger(cluster, None, report)
        for remap in report.remaps:
            log.warning("cluster %s: remap of schedule %s without %s: job %s %s", cluster.pk, remap["schedule"],
                        ", ".join(remap["fail"]), remap["job"], remap["state"])  # fmt: skip


def _trigger(cluster: Cluster, threshold: float | None, report: WatchReport) -> None:
    """Start a remap job for each application's latest pushed schedule that has tasks on a down node."""
    down = set(cluster.nodes.exclude(status=ComputeNode.Status.READY).values_list("name", flat=True))
    if not down:
        return
    applications = Schedule.objects.filter(cluster=cluster).values_list("application_id", flat=True).distinct()
    for application_id in sorted(set(applications)):
        schedule = remapping.latest_pushed(application_id, cluster)
        if schedule is None:
            continue
        lost_on = sorted(set(schedule.assignments.filter(processor__in=down).values_list("processor", flat=True)))
        if not lost_on:
            continue
        if Job.objects.filter(
            kind="remap", fleet_id=cluster.fleet_id, arguments__schedule=schedule.pk, arguments__trigger="watch"
        ).exists():
            continue  # one watcher remap per schedule; its outcome is on the job and the event
        arguments = {
            "schedule": schedule.pk,
            "fail": lost_on,
            "what_if": False,
            "threshold": threshold,
            "trigger": RemapEvent.Trigger.WATCH,
        }
        job = start_job(Heft4kJob.REMAP, cluster.fleet, arguments)
        event = RemapEvent.objects.filter(job=job).first()
        report.remaps.append(
            {
                "job": str(job.pk),
                "schedule": schedule.pk,
                "fail": lost_on,
                "state": job.state,
                "remap": event.pk if event else None,
                "error": job.error,
            }
        )
