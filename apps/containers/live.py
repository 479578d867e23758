"""Live state of a pushed placement's containers (registered with the cluster's watcher, ``apps.clusters.live``).

The pods of a container's Deployment carry its ``continuum.io/deployment`` label (see
:func:`apps.containers.kube.deployment_manifest`). A ContainerDeployment shows the Deployment's newest pod:
a new pod replaces the stored one, while a terminating or deleted pod only updates the row that shows it
(with the ``Recreate`` strategy the old pod goes while the new one comes).
"""

from __future__ import annotations

from apps.clusters.live import event_text, live_values, store
from apps.clusters.models import Cluster
from apps.kube.gateway import PREFIX, PodState

from .models import ContainerDeployment


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
