"""Live state of RT-Kube's pods (registered with the cluster's watcher, ``apps.clusters.live``).

RT pods already have their stored row (:class:`~apps.realtime.models.RTPod`, the RT scheduler's ledger, which
also records the node it binds them to): the watcher adds the phase and the newest event to the row of a pod
the scheduler knows, and creates none.
"""

from __future__ import annotations

from apps.clusters.live import live_values, store
from apps.clusters.models import Cluster
from apps.kube.gateway import PodState

from .models import RTPod


def store_pod_state(cluster: Cluster, state: PodState) -> int:
    rows = RTPod.objects.filter(cluster=cluster, namespace=state.namespace, name=state.name)
    if state.uid:
        rows = rows.filter(uid__in=["", state.uid])
    # A deleted pod keeps its last phase: the RT scheduler records the deletion (deleted_at).
    values = live_values(state) if state.deleted else live_values(state, phase=state.phase)
    return store(rows, values) if values else 0
