"""What-if placement (thesis 3.4, Algorithms 3-4): the engine's RT-Kube pass over containers on a stored cluster.

The cluster's nodes come from its node rows (RT attributes, taints, and the monitor's active timed taints);
with ``with_bound`` the pass starts from the reservations of the pods the RT scheduler has bound (the
ledger), as the real scheduler would. The result is the engine's ``PlacementPlan``.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping
from dataclasses import replace
from typing import Any

from django.utils import timezone

from apps.clusters.models import Cluster
from continuum.engine.core.errors import InputError
from continuum.engine.core.placement import PlacementPlan
from continuum.engine.core.taints import STATUS_TAINTS
from continuum.engine.rtkube import rt_kube, rt_kube_vec
from continuum.engine.rtkube.rt_model import (
    NONE,
    RT_TAINT,
    RTContainer,
    RTNode,
    Taint,
    default_tolerations,
    rt_nodes,
    rtset_from_dict,
)

from .models import NodeTaint, RealTime, RTDecision, RTPod, RTPolicy

PARAM_KEYS = ("k", "b_score_argument", "sort_tiebreak")


def db_rt_nodes(cluster: Cluster) -> list[RTNode]:
    """RT-Kube's view of :meth:`Cluster.to_engine` (nodes that are not Ready carry their status taint), with the
    monitor's active taints, which carry their expiry (``until``), and the RealTime taint on every RT node."""
    if not cluster.nodes.exists():
        return []
    now = timezone.now()
    ids = dict(cluster.nodes.values_list("name", "pk"))
    timed: dict[int, list[NodeTaint]] = {}
    for t in NodeTaint.objects.filter(cluster=cluster, lifted_at__isnull=True):
        timed.setdefault(t.node_id, []).append(t)
    out = []
    for node in rt_nodes(cluster.to_engine()):
        mine = timed.get(ids[node.name], [])
        # The monitor's taints count with their expiry (one past its time is as good as lifted).
        kept = [t for t in node.taints if not any(t.key == m.key and t.effect == m.effect for m in mine)]
        taints = [t for t in kept if t not in STATUS_TAINTS.values()]
        taints += [Taint(m.key, m.value, m.effect, until=m.expires_at.timestamp()) for m in mine if m.expires_at > now]
        if node.rt and not any(t.key == RT_TAINT.key for t in taints):
            taints.append(RT_TAINT)
        taints += [t for t in kept if t in STATUS_TAINTS.values()]
        out.append(replace(node, taints=tuple(taints)))
    return out


def bound_ledger(cluster: Cluster, nodes: Iterable[RTNode], replaced: Iterable[str] = ()) -> rt_kube.Ledger:
    """The reservations of the pods bound now (the RT scheduler's ledger rows), except the pods of the RealTime
    objects named in ``replaced`` (the what-if places those again)."""
    names = [n.name for n in nodes]
    skip = set(replaced)
    bindings = {}
    pods = RTPod.objects.filter(cluster=cluster, deleted_at__isnull=True).exclude(node="").select_related("realtime")
    for p in pods:
        if p.node in names and not (p.realtime_id and p.realtime.name in skip):
            bindings[p.key] = rt_kube.Binding(p.key, p.node, p.utilization or 0.0, p.cpu, p.memory_mib, p.criticality)
    return rt_kube.Ledger(names, bindings)


def params_for(cluster: Cluster, overrides: Mapping[str, Any] | None) -> rt_kube.RTKubeParams:
    policy = RTPolicy.for_cluster(cluster)
    kwargs = {"k": policy.k, "b_score_argument": policy.b_score_argument, "sort_tiebreak": policy.sort_tiebreak}
    for key, value in (overrides or {}).items():
        if key not in PARAM_KEYS:
            raise InputError(f"unknown parameter {key!r} (known: {', '.join(PARAM_KEYS)})", "params")
        kwargs[key] = value
    return rt_kube.RTKubeParams(**kwargs)


def containers_for(
    cluster: Cluster, realtime_ids: list[int] | None, rtset: Mapping | None, node_names: list[str]
) -> list[RTContainer]:
    containers: list[RTContainer] = []
    if rtset is not None:
        containers += rtset_from_dict(rtset, node_names)
    rows = RealTime.objects.filter(cluster=cluster).prefetch_related("wcets__node")
    if realtime_ids is not None:
        rows = rows.filter(pk__in=realtime_ids)
        missing = sorted(set(realtime_ids) - set(rows.values_list("pk", flat=True)))
        if missing:
            raise InputError(f"RealTime {missing[0]} is not in cluster {cluster.name!r}", "realtimes")
    elif rtset is not None:
        rows = rows.none()
    containers += [row.to_engine(node_names) for row in rows]
    seen: set[str] = set()
    for c in containers:
        if c.name in seen:
            raise InputError(f"container {c.name!r} appears twice", "containers")
        seen.add(c.name)
    if not containers:
        raise InputError(f"cluster {cluster.name!r} has no RealTime objects and no containers were given", "containers")
    return containers


def whatif(
    cluster: Cluster,
    realtime_ids: list[int] | None = None,
    rtset: Mapping | None = None,
    params: Mapping[str, Any] | None = None,
    with_bound: bool = True,
    full: str = "auto",
    explain: str | None = None,
) -> PlacementPlan:
    nodes = db_rt_nodes(cluster)
    if not nodes:
        raise InputError(f"cluster {cluster.name!r} has no nodes", "cluster")
    names = [n.name for n in nodes]
    containers = containers_for(cluster, realtime_ids, rtset, names)
    ledger = bound_ledger(cluster, nodes, [c.name for c in containers]) if with_bound else None
    return rt_kube_vec.schedule(
        containers, nodes, params_for(cluster, params), ledger, now=time.time(), full=full, explain=explain
    )


def decision_container(decision: RTDecision, node_names: list[str]) -> RTContainer:
    """The engine's container of a stored decision's pod, from its ledger row and its RealTime object.

    The pod's own tolerations are not stored: the container carries its class's default (RT pods tolerate
    the RealTime taint, standard pods nothing), as the pods Continuum creates do."""
    pod = RTPod.objects.filter(cluster_id=decision.cluster_id, namespace=decision.namespace, name=decision.pod).first()
    key = f"{decision.namespace}/{decision.pod}"
    cpu, mem = (pod.cpu, pod.memory_mib) if pod else (0.0, 0.0)
    realtime = decision.realtime or (pod.realtime if pod else None)
    if realtime is None:
        return RTContainer(key, NONE, stateless=bool(pod and pod.stateless), cpu=cpu, memory_mib=mem)
    base = realtime.to_engine(node_names)
    return RTContainer(
        key,
        base.criticality,
        base.period,
        base.deadline,
        base.wcet,
        base.stateless or bool(pod and pod.stateless),
        cpu or base.cpu,
        mem or base.memory_mib,
        default_tolerations(base.criticality),
        0.0,
    )


def why_not(decision: RTDecision, node: str | None = None) -> dict[str, Any]:
    """The full explanation of one stored decision, on demand: every node's verdict (or ``node``'s) for the
    decision's pod, by the scheduler's filters and scores (``rt_kube_vec.why_not``), against the cluster as
    it is now (its nodes, taints and the reservations of the other pods bound). InputError for a node the
    cluster does not have or a pod whose RealTime object is no longer valid."""
    cluster = decision.cluster
    nodes = db_rt_nodes(cluster)
    names = [n.name for n in nodes]
    if node is not None and node not in names:
        raise InputError(f"cluster {cluster.name!r} has no node {node!r}", "node")
    container = decision_container(decision, names)
    ledger = bound_ledger(cluster, nodes)
    ledger.release(container.name)  # the pod itself, if bound, is judged as if it were not
    verdicts = rt_kube_vec.why_not(container, nodes, ledger, params_for(cluster, None), time.time(), node)
    return {
        "decision": decision.pk,
        "pod": container.name,
        "chosen": decision.node or None,
        "as_of": timezone.now().isoformat(),
        "nodes": len(names),
        "verdicts": [v.to_dict() for v in verdicts],
    }
