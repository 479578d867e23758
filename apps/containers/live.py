"""Live state of a pushed placement's containers (registered with the cluster's watcher, ``apps.clusters.live``).

The pods of a container's Deployment carry its ``continuum.io/deployment`` label (see
:func:`apps.containers.kube.deployment_manifest`). A ContainerDeployment shows the Deployment's newest pod:
a new pod replaces the stored one, while a terminating or deleted pod only updates the row that shows it
(with the ``Recreate`` strategy the old pod goes while the new one comes).
"""

from __future__ import annotations

from django.contrib.auth.decorators import login_required
from django.db.models import F
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404

from apps.clusters.live import event_text, live_values, store
from apps.clusters.models import Cluster
from apps.kube.gateway import PREFIX, PodState
from apps.ui.helpers import scoped
from apps.ui.live import LIMIT, LivePod, live_response

from .models import ContainerDeployment, Placement


def store_pod_state(cluster: Cluster, state: PodState) -> int:
    deployment = state.labels.get(f"{PREFIX}/deployment")
    if not deployment:
        return 0
    rows = ContainerDeployment.objects.filter(
        placement__cluster=cluster, namespace=state.namespace, deployment=deployment
    ).exclude(state=ContainerDeployment.State.SUPERSEDED)
    if state.deleted or state.terminating:
        rows = rows.filter(pod_name=state.name)
    values = live_values(state, pod_name=state.name, pod_phase=state.phase, pod_node=state.node)
    # Rows that showed another pod take this one with its event (none yet: empty); the others keep theirs.
    replaced = store(rows.exclude(pod_name=state.name), {**values, "pod_event": event_text(state)})
    return replaced + store(rows.filter(pod_name=state.name), values)


def placement_pods(placement: Placement) -> tuple[list[LivePod], int]:
    """The pods of ``placement``'s pushed Deployments now, next to the node the placement chose (newest change
    first, at most LIMIT), and how many Deployments were pushed."""
    pushed = placement.deployments.exclude(state__in=[ContainerDeployment.State.NOT_PUSHED])
    rows = pushed.order_by(F("pod_state_at").desc(nulls_last=True), "container")[:LIMIT]

    def label(d: ContainerDeployment) -> str:
        superseded = d.state == ContainerDeployment.State.SUPERSEDED
        return f"container {d.container}" + (" (superseded by a newer placement)" if superseded else "")

    pods = [LivePod.from_row(d, label(d), d.node) for d in rows]
    return pods, pushed.count()


@login_required
def placement_live(request: HttpRequest, pk: int) -> HttpResponse:
    """``/ros/placements/<pk>/live/``: the placement's pods now (JSON for ``ui/includes/live_pods.html``)."""
    placement = get_object_or_404(scoped(request, Placement.objects.all()), pk=pk)
    pods, total = placement_pods(placement)
    return live_response(pods, total, empty="No container of this placement was pushed to Kubernetes yet.")
