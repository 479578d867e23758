"""Push a container placement to Kubernetes: one Deployment per container (thesis 3.3.1; spec 02 sections 3, 5).

Each Deployment has one replica, ``hostNetwork: true`` (the thesis does not isolate containers: ROS nodes use
the host's IP and ports, no NAT), resource requests from the container's CPU and memory (no limits: CFS quotas
would override the priorities of ROS threads, spec 02 section 7.3), the image of the container's image plan (or
``CONTINUUM_POD_IMAGE``) and its ROS nodes in ``CONTINUUM_ROS_NODES``.

**Pinning to the chosen node: a ``nodeSelector`` on ``kubernetes.io/hostname``, not ``nodeName``.** Together
with ``kubernetes.io/arch`` (the node's architecture, one of the image's platforms) the selector lets
kube-scheduler (or K3s', or KubeEdge's cloud scheduler) bind the pod to exactly that node while still running
its filters on the live cluster: if the node no longer fits (resources taken meanwhile, a new taint) the pod
stays Pending with an event that says why. ``nodeName`` would bypass the scheduler; the kubelet then rejects a
pod that does not fit (``OutOfcpu``) and the ReplicaSet creates another, without end. The hostname value is
the node's own ``kubernetes.io/hostname`` label when the node was synced from the API (it may differ from the
node name), else the node name. The strategy is ``Recreate``: with the host network an old and a new pod of
the same container would bind the same ports, and a ROS node must not run twice.

**Idempotence.** A Deployment is named after (clustering, container) -- or (placement, container) for a
placement of a containers document -- so pushing another placement of the same clustering moves the same
Deployments instead of starting the ROS nodes twice. The manifest's SHA-256 is kept in the
``continuum.io/spec-hash`` annotation: a Deployment whose hash matches is left untouched (a second push
changes nothing, not even the resourceVersion), another one is replaced. Failures are recorded per container.
"""

from __future__ import annotations

import hashlib
import json
import math
from typing import Any

from django.conf import settings
from django.db import transaction

from apps.clusters.kube import api_client_for
from apps.kube.gateway import (
    API_ERRORS,
    MANAGED_BY,
    PREFIX,
    Deployments,
    KubeError,
    Progress,
    describe,
)
from apps.kube.gateway import dns_part as _dns_part
from apps.kube.gateway import label_value as _label_value
from continuum.engine.core.cluster import Cluster as EngineCluster

from .models import ContainerDeployment, Placement

HASH_ANNOTATION = f"{PREFIX}/spec-hash"


def group_key(placement: Placement) -> str:
    """What the Deployments of a placement are named after: its clustering, else the placement itself."""
    return f"clustering-{placement.clustering_id}" if placement.clustering_id else f"placement-{placement.pk}"


def deployment_name(placement: Placement, container: str) -> str:
    """``<graph>-<container>-<hash>``: DNS-1123 safe, at most 56 characters, unique per (group, container)."""
    group = group_key(placement)
    digest = hashlib.sha256(f"{group}/{container}".encode()).hexdigest()[:10]
    base = placement.rosgraph.name if placement.rosgraph_id else "containers"
    return f"{_dns_part(base, 20)}-{_dns_part(container, 24)}-{digest}"


def _cpu(cores: float) -> str:
    """Millicores, in the canonical form the API server stores (``1500m``, but ``3`` rather than ``3000m``)."""
    milli = max(0, round(cores * 1000))
    return str(milli // 1000) if milli % 1000 == 0 else f"{milli}m"


def _memory(mib: float) -> str:
    whole = max(0, math.ceil(mib - 1e-9))
    return f"{whole}Mi" if whole else "0"


def deployment_manifest(
    placement: Placement, spec: dict[str, Any], node: str, cluster: EngineCluster, name: str
) -> dict[str, Any]:
    """The Deployment of one placed container (``spec``: its entry of the resolved containers document)."""
    target = cluster.nodes[node]
    labels = target.all_labels()
    selector = {
        **{str(k): str(v) for k, v in (spec.get("node_selector") or {}).items()},
        "kubernetes.io/arch": target.arch,
        "kubernetes.io/hostname": labels["kubernetes.io/hostname"],
    }
    tolerations = []
    for t in spec.get("tolerations") or []:
        item = {k: v for k, v in t.items() if v not in ("", None)}
        if item:
            tolerations.append(item)
    match = {f"{PREFIX}/deployment": name}
    meta_labels = {
        **MANAGED_BY,
        f"{PREFIX}/group": group_key(placement),
        f"{PREFIX}/placement": str(placement.pk),
        f"{PREFIX}/container": _label_value(spec["name"]),
    }
    env = [
        {"name": "CONTINUUM_CONTAINER", "value": spec["name"]},
        {"name": "CONTINUUM_ROS_NODES", "value": " ".join(spec.get("nodes", []))},
        {"name": "CONTINUUM_PLACEMENT", "value": str(placement.pk)},
    ]
    pod_spec: dict[str, Any] = {
        "hostNetwork": True,
        # With the host network, cluster DNS only resolves when asked for explicitly.
        "dnsPolicy": "ClusterFirstWithHostNet",
        "nodeSelector": selector,
        "containers": [
            {
                "name": "ros",
                "image": spec.get("image") or settings.CONTINUUM_POD_IMAGE,
                "env": env,
                "resources": {
                    "requests": {"cpu": _cpu(spec.get("cpu", 0.0)), "memory": _memory(spec.get("memory_mib", 0.0))}
                },
            }
        ],
    }
    if tolerations:
        pod_spec["tolerations"] = tolerations
    body = {
        "apiVersion": "apps/v1",
        "kind": "Deployment",
        "metadata": {
            "name": name,
            "labels": meta_labels,
            "annotations": {
                f"{PREFIX}/container": spec["name"],
                f"{PREFIX}/node": node,
                f"{PREFIX}/policy": placement.policy,
                f"{PREFIX}/ros-nodes": ",".join(spec.get("nodes", [])),
                f"{PREFIX}/priority": str(spec.get("priority", 0)),
            },
        },
        "spec": {
            "replicas": 1,
            "strategy": {"type": "Recreate"},
            "selector": {"matchLabels": match},
            "template": {"metadata": {"labels": {**MANAGED_BY, **match}}, "spec": pod_spec},
        },
    }
    digest = hashlib.sha256(json.dumps(body, sort_keys=True).encode()).hexdigest()
    body["metadata"]["annotations"][HASH_ANNOTATION] = digest
    return body


def push_placement(placement: Placement, progress: Progress | None = None) -> dict[str, Any]:
    """Create or update one Deployment per container in ``cluster.namespace``; returns counts.

    Records a :class:`ContainerDeployment` per container (applied/failed and why). Raises :class:`KubeError`
    with a summary when any container could not be applied (the records are stored first).
    """
    progress = progress or (lambda percent, message: None)
    cluster = placement.cluster
    if cluster is None:
        raise KubeError(f"placement {placement.pk} has lost its cluster (deleted)")
    api_client = api_client_for(cluster)
    namespace = cluster.namespace or settings.CONTINUUM_DEFAULT_NAMESPACE
    engine = placement.engine_cluster()
    placed = placement.placed()
    specs = {c["name"]: c for c in placement.containers["containers"]}
    order = [d.item for d in placement.engine_plan().decisions]  # decision order = priority order
    names = {c: deployment_name(placement, c) for c in order}
    outcomes: dict[str, tuple[bool, str]] = {}
    counts = {"created": 0, "updated": 0, "unchanged": 0}
    fatal = None
    with api_client:
        pusher = Deployments(api_client, namespace, HASH_ANNOTATION)
        try:
            problems, current = pusher.prepare(f"{PREFIX}/group={group_key(placement)}")
            progress(5, f"namespace {namespace}: {len(current)} of {len(order)} Deployments exist")
            work: list[str] = []
            for container in order:
                node = placed.get(container)
                if node is None:
                    outcomes[container] = (False, "pending in the plan: no node passed the filters")
                elif node not in problems:
                    outcomes[container] = (False, f"node {node!r} not found in the Kubernetes API")
                elif problems[node]:
                    outcomes[container] = (False, problems[node])
                else:
                    work.append(container)
            bodies = [
                (deployment_manifest(placement, specs[c], placed[c], engine, names[c]), current.get(names[c]))
                for c in work
            ]
            # Up to CONTINUUM_KUBE_PUSH_CONCURRENCY applies in flight, started in decision (priority) order.
            results, fatal = pusher.apply_all(
                bodies,
                lambda done: progress(5 + 90 * done / max(len(work), 1), f"applied {done}/{len(work)} Deployments"),
            )
            for container, result in zip(work, results, strict=True):
                outcomes[container] = result
                if result[0]:
                    counts[result[1]] += 1
        except API_ERRORS as exc:
            fatal = describe(exc, api_client.configuration.host)
            for container in order:
                outcomes.setdefault(container, (False, fatal))
    with transaction.atomic():
        # One upsert for all the containers (not a query or two per container): the row of a container pushed
        # before is updated in place, keeping what the pod watcher stored on it.
        state = ContainerDeployment.State
        ContainerDeployment.objects.bulk_create(
            [
                ContainerDeployment(
                    placement=placement,
                    container=container,
                    node=placed.get(container) or "",
                    deployment=names[container],
                    namespace=namespace,
                    state=state.APPLIED if outcomes[container][0] else state.FAILED,
                    message=outcomes[container][1][:500],
                )
                for container in order
            ],
            update_conflicts=True,
            unique_fields=["placement", "container"],
            update_fields=["node", "deployment", "namespace", "state", "message", "updated"],
        )
        # The Deployments just applied now follow this placement, not an older one of the same clustering.
        applied = [names[c] for c in order if outcomes[c][0]]
        ContainerDeployment.objects.filter(
            deployment__in=applied, namespace=namespace, state=ContainerDeployment.State.APPLIED
        ).exclude(placement=placement).filter(placement__cluster=cluster).update(
            state=ContainerDeployment.State.SUPERSEDED, message=f"superseded by placement {placement.pk}"
        )
    failed = [c for c in order if not outcomes[c][0]]
    if failed:
        if fatal:
            raise KubeError(f"push of placement {placement.pk} to cluster {cluster.name!r} failed: {fatal}")
        shown = "; ".join(f"{c}: {outcomes[c][1]}" for c in failed[:5])
        more = f" and {len(failed) - 5} more" if len(failed) > 5 else ""
        raise KubeError(f"{len(failed)} of {len(order)} containers of placement {placement.pk} failed: {shown}{more}")
    return {"placement": placement.pk, "namespace": namespace, "deployments": len(order), **counts, "failed": 0}
