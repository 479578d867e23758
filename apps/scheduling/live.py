"""Live state of a pushed schedule's pods (registered with the cluster's watcher, ``apps.clusters.live``).

A schedule's pods carry the ``continuum.io/schedule`` and ``continuum.io/application`` labels
(:func:`apps.kube.pods.pod_manifest`); the assignments that name the pod (``pod_name``; a remapped schedule
keeps the pods of the schedule it came from) get its phase, node and newest event.
"""

from __future__ import annotations

from apps.clusters.live import live_values, store
from apps.clusters.models import Cluster
from apps.kube.gateway import PREFIX, PodState

from .models import Assignment


def store_pod_state(cluster: Cluster, state: PodState) -> int:
    application = state.labels.get(f"{PREFIX}/application")
    if not application or f"{PREFIX}/schedule" not in state.labels or not application.isdigit():
        return 0
    rows = Assignment.objects.filter(
        schedule__cluster=cluster, schedule__application_id=int(application), pod_name=state.name
    )
    return store(rows, live_values(state, pod_phase=state.phase, pod_node=state.node))
