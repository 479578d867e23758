"""Live state of RT-Kube's pods (registered with the cluster's watcher, ``apps.clusters.live``).

RT pods already have their stored row (:class:`~apps.realtime.models.RTPod`, the RT scheduler's ledger, which
also records the node it binds them to): the watcher adds the phase and the newest event to the row of a pod
the scheduler knows, and creates none.
"""

from __future__ import annotations

from django.contrib.auth.decorators import login_required
from django.db.models import F
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404

from apps.clusters.live import live_values, store
from apps.clusters.models import Cluster
from apps.kube.gateway import PodState
from apps.ui.live import LIMIT, LivePod, live_response

from .models import RTPod


def store_pod_state(cluster: Cluster, state: PodState) -> int:
    rows = RTPod.objects.filter(cluster=cluster, namespace=state.namespace, name=state.name)
    if state.uid:
        rows = rows.filter(uid__in=["", state.uid])
    # A deleted pod keeps its last phase: the RT scheduler records the deletion (deleted_at).
    values = live_values(state) if state.deleted else live_values(state, phase=state.phase)
    return store(rows, values) if values else 0


def rt_pods(cluster: Cluster) -> tuple[list[LivePod], int]:
    """The cluster's RT pods that are not deleted, with their phase and newest event (newest change first, at
    most LIMIT): the node is the one RT-Kube bound the pod to."""
    alive = RTPod.objects.filter(cluster=cluster, deleted_at__isnull=True)
    rows = alive.select_related("realtime").order_by(F("pod_state_at").desc(nulls_last=True), "namespace", "name")
    pods = [
        LivePod(
            label=(f"RealTime {p.realtime.name}" if p.realtime else p.container_name or "pod")
            + (f" ({p.criticality})" if p.criticality != "NONE" else ""),
            pod=f"{p.namespace}/{p.name}",
            node=p.node,
            phase=p.phase,
            event=p.pod_event,
            at=p.pod_state_at,
        )
        for p in rows[:LIMIT]
    ]
    return pods, alive.count()


@login_required
def cluster_live(request: HttpRequest, pk: int) -> HttpResponse:
    """``/realtime/clusters/<pk>/live/``: the cluster's RT pods now (JSON for ``ui/includes/live_pods.html``)."""
    from .views import clusters_of

    cluster = get_object_or_404(clusters_of(request), pk=pk)
    pods, total = rt_pods(cluster)
    return live_response(pods, total, empty="No RT pod on this cluster.")
