"""Live state of a pushed schedule's pods (registered with the cluster's watcher, ``apps.clusters.live``).

A schedule's pods carry the ``continuum.io/schedule`` and ``continuum.io/application`` labels
(:func:`apps.kube.pods.pod_manifest`); the assignments that name the pod (``pod_name``; a remapped schedule
keeps the pods of the schedule it came from) get its phase, node and newest event. The schedule page shows
them (:func:`schedule_live`, polled by ``ui/includes/live_pods.html``).
"""

from __future__ import annotations

from django.contrib.auth.decorators import login_required
from django.db.models import F
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404

from apps.clusters.live import live_values, store
from apps.clusters.models import Cluster
from apps.kube.gateway import PREFIX, PodState
from apps.ui.helpers import scoped
from apps.ui.live import LIMIT, LivePod, live_response

from .models import Assignment, Schedule


def store_pod_state(cluster: Cluster, state: PodState) -> int:
    application = state.labels.get(f"{PREFIX}/application")
    if not application or f"{PREFIX}/schedule" not in state.labels or not application.isdigit():
        return 0
    rows = Assignment.objects.filter(
        schedule__cluster=cluster, schedule__application_id=int(application), pod_name=state.name
    )
    return store(rows, live_values(state, pod_phase=state.phase, pod_node=state.node))


def schedule_pods(schedule) -> tuple[list[LivePod], int]:
    """The pushed pods of ``schedule`` with their live state, newest change first (at most LIMIT), and how
    many there are: which pods run where now, next to the node the plan gave their task."""
    pushed = schedule.assignments.exclude(pod_name="")
    rows = pushed.order_by(F("pod_state_at").desc(nulls_last=True), "processor", "start").only(
        "task", "frame", "processor", "pod_name", "pod_phase", "pod_node", "pod_event", "pod_state_at"
    )[:LIMIT]

    def label(a: Assignment) -> str:
        return f"task {a.task}" + (f" (frame {a.frame})" if a.frame else "")

    pods = [LivePod.from_row(a, label(a), a.processor) for a in rows]
    return pods, pushed.count()


@login_required
def schedule_live(request: HttpRequest, pk: int) -> HttpResponse:
    """``/schedules/<pk>/live/``: the schedule's pods now (JSON for ``ui/includes/live_pods.html``)."""
    schedule = get_object_or_404(scoped(request, Schedule.objects.all()), pk=pk)
    pods, total = schedule_pods(schedule)
    return live_response(pods, total, empty="No pod of this schedule was pushed to Kubernetes yet.")
