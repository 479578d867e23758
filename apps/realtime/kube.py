"""RT-Kube's Kubernetes data and its access to a cluster's API (thesis 3.4, Fig. 3.32; spec 03 sections 3, 4.4, 5.4).

The domain data stays here as plain dicts: the two CustomResourceDefinitions (apiextensions v1, with status
subresources) ``realtimes.rt.scheduling`` (Listing 3.33) and ``monitorings.rt.monitoring`` (Listing 3.37),
the node labels carrying RT attributes, the replacement of an evicted pod. Every call goes through the
Kubernetes gateway (:class:`apps.kube.gateway.Kube`: the bind phase, the scheduler's explanations, the
eviction, node taints written with optimistic concurrency, custom objects), built by :func:`kube_for` from the
cluster's validated kubeconfig.
"""

from __future__ import annotations

import copy
import hashlib
import logging
import threading
from collections.abc import Iterable
from datetime import datetime

from apps.clusters.kube import api_client_for
from apps.clusters.models import Cluster
from apps.kube.gateway import KUBE_ERRORS, Kube, cores, mib, problem
from apps.kube.parallel import concurrency
from continuum.engine.rtkube.rt_model import RT_SCHEDULER_NAME

log = logging.getLogger(__name__)
REALTIME_GROUP, REALTIME_VERSION, REALTIME_PLURAL = "rt.scheduling", "v1", "realtimes"
MONITORING_GROUP, MONITORING_VERSION, MONITORING_PLURAL = "rt.monitoring", "v1alpha1", "monitorings"
#: Node labels that carry the RT attributes Continuum keeps (spec 03 3.3 [PROPOSAL]).
CRITICALITY_LABEL = "rt.scheduling/criticality"
THRESHOLD_LABEL = "rt.scheduling/threshold"

_POSITIVE = {"type": "number", "minimum": 0, "exclusiveMinimum": True}


def _crd(group: str, version: str, plural: str, kind: str, short: str, spec: dict, columns: list) -> dict:
    return {
        "apiVersion": "apiextensions.k8s.io/v1",
        "kind": "CustomResourceDefinition",
        "metadata": {"name": f"{plural}.{group}", "labels": {"app.kubernetes.io/managed-by": "continuum"}},
        "spec": {
            "group": group,
            "scope": "Namespaced",
            "names": {"plural": plural, "singular": kind.lower(), "kind": kind, "shortNames": [short]},
            "versions": [
                {
                    "name": version,
                    "served": True,
                    "storage": True,
                    "subresources": {"status": {}},
                    "additionalPrinterColumns": columns,
                    "schema": {
                        "openAPIV3Schema": {
                            "type": "object",
                            "required": ["spec"],
                            "properties": {
                                "spec": spec,
                                "status": {"type": "object", "x-kubernetes-preserve-unknown-fields": True},
                            },
                        }
                    },
                }
            ],
        },
    }


def crd_manifests() -> list[dict]:
    """The RealTime and Monitoring CRDs with OpenAPI schemas (enum criticality, positive numbers, unique nodes)."""
    realtime_spec = {
        "type": "object",
        "required": ["criticality", "rtPeriod", "rtDeadline", "rtWcets"],
        "properties": {
            # D exists on the ASIL-derived scale but needs an ASIL-D capable platform (thesis 3.4).
            "criticality": {"type": "string", "enum": ["A", "B", "C"]},
            "rtPeriod": dict(_POSITIVE, description="period P (ms)"),
            "rtDeadline": dict(_POSITIVE, description="relative deadline D <= P (ms)"),
            "rtWcets": {
                "type": "array",
                "minItems": 1,
                # A list keyed by node: the API server rejects a node given twice.
                "x-kubernetes-list-type": "map",
                "x-kubernetes-list-map-keys": ["node"],
                "items": {
                    "type": "object",
                    "required": ["node", "rtWcet"],
                    "properties": {
                        "node": {"type": "string", "minLength": 1},
                        "rtWcet": dict(_POSITIVE, description="WCET on this node, <= D (ms)"),
                    },
                },
            },
            "stateless": {"type": "boolean"},
            "cpu": dict(_POSITIVE, description="CPU request (cores)"),
            "memoryMib": dict(_POSITIVE, description="memory request (MiB)"),
        },
    }
    monitoring_spec = {
        "type": "object",
        "required": ["node", "containerName", "missedDeadlinesPeriod", "missedDeadlinesTotal"],
        "properties": {
            "node": {"type": "string", "minLength": 1},
            "containerName": {"type": "string", "minLength": 1},
            "pod": {"type": "string"},
            "missedDeadlinesPeriod": {"type": "integer", "minimum": 0},
            "missedDeadlinesTotal": {"type": "integer", "minimum": 0},
            "sentAt": {"type": "string"},
            "missAt": {"type": "string"},
        },
    }
    return [
        _crd(
            REALTIME_GROUP,
            REALTIME_VERSION,
            REALTIME_PLURAL,
            "RealTime",
            "rt",
            realtime_spec,
            [
                {"name": "Criticality", "type": "string", "jsonPath": ".spec.criticality"},
                {"name": "Period", "type": "number", "jsonPath": ".spec.rtPeriod"},
                {"name": "Deadline", "type": "number", "jsonPath": ".spec.rtDeadline"},
            ],
        ),
        _crd(
            MONITORING_GROUP,
            MONITORING_VERSION,
            MONITORING_PLURAL,
            "Monitoring",
            "rtmon",
            monitoring_spec,
            [
                {"name": "Node", "type": "string", "jsonPath": ".spec.node"},
                {"name": "Container", "type": "string", "jsonPath": ".spec.containerName"},
                {"name": "Period", "type": "integer", "jsonPath": ".spec.missedDeadlinesPeriod"},
                {"name": "Total", "type": "integer", "jsonPath": ".spec.missedDeadlinesTotal"},
            ],
        ),
    ]


def replacement_pod(pod: dict) -> dict:
    """A fresh, unbound copy of an evicted pod nobody owns: what its ReplicaSet would create (spec 03 5.4)."""
    meta = pod["metadata"]
    spec = copy.deepcopy(pod.get("spec") or {})
    spec.pop("nodeName", None)
    return {
        "apiVersion": "v1",
        "kind": "Pod",
        "metadata": {
            "name": meta["name"],
            "namespace": meta["namespace"],
            "labels": dict(meta.get("labels") or {}),
            "annotations": dict(meta.get("annotations") or {}),
        },
        "spec": spec,
    }


# ---- one client per cluster and process -------------------------------------------------------------------
_CLIENTS: dict[tuple[int, str], Kube] = {}
_LOCK = threading.Lock()


def kube_for(cluster: Cluster) -> Kube:
    """A cached :class:`Kube` for the cluster (rebuilt when its kubeconfig or context changes)."""
    digest = hashlib.sha256(f"{cluster.kube_context}\n{cluster.kubeconfig}".encode()).hexdigest()
    key = (cluster.pk, digest)
    kube = _CLIENTS.get(key)
    if kube is not None:
        return kube
    # Built outside the lock (validating the kubeconfig and making the client takes tens of ms on a busy
    # machine): another cluster's eviction must not wait for it. Two threads may build one each; one is kept.
    # Shared by the RT scheduler's Binding pool, its Events, its cycle's reads and the RT sync: a connection
    # each, kept warm (see apps.realtime.scheduler).
    pool = binders() + concurrency() + 4
    built = Kube(api_client_for(cluster, pool=pool), cluster.name, component=RT_SCHEDULER_NAME)
    with _LOCK:
        kube = _CLIENTS.get(key)
        if kube is None:
            for old in [k for k in _CLIENTS if k[0] == cluster.pk]:
                _CLIENTS.pop(old)
            kube = _CLIENTS[key] = built
    if kube is not built:
        built.api_client.close()
    return kube


def binders() -> int:
    """Bindings the RT scheduler has in flight at most: four times a push's bound, at most 64. kube-scheduler
    binds each pod in a goroutine of its own; a Binding waits 60-100 ms for a loaded API server, so a cycle's
    burst of decisions queued behind fewer threads waited hundreds of ms before its Bindings went out."""
    return min(4 * concurrency(), 64)


def warm(cluster: Cluster) -> bool:
    """Build the cluster's client (:func:`kube_for`) and open a connection to its API with one cheap read (the
    server's version), so that the first eviction pays no TLS handshake; whether the API answered."""
    try:
        kube_for(cluster).version()
    except KUBE_ERRORS as exc:
        log.info("cluster %s: API not warmed: %s", cluster.pk, problem(exc))
        return False
    return True


def has_api(cluster: Cluster) -> bool:
    return bool(cluster.kubeconfig.strip())


def requests_of(pod: dict) -> tuple[float, float]:
    """The pod's CPU (cores) and memory (MiB) requests, summed over its containers."""
    cpu = mem = 0.0
    for c in (pod.get("spec") or {}).get("containers") or []:
        req = (c.get("resources") or {}).get("requests") or {}
        cpu += cores(req.get("cpu")) or 0.0
        mem += mib(req.get("memory")) or 0.0
    return cpu, mem


def parse_time(stamp: str | None) -> datetime | None:
    if not stamp:
        return None
    try:
        return datetime.fromisoformat(stamp.replace("Z", "+00:00"))
    except ValueError:
        return None


def names(items: Iterable[dict]) -> list[str]:
    return [i["metadata"]["name"] for i in items]
