"""Fixtures of the RT-Kube app tests: a cluster with RT nodes, RealTime objects and pods in the ledger."""

import pytest

#: node0, node1: RT nodes for A/B; node2: the C node; node3: no RT kernel. 4 cores each: threshold 3.8.
RT_NODES = {"node0": ("A", True), "node1": ("A", True), "node2": ("C", True), "node3": ("", False)}


def make_rt(cluster, name, criticality, period, deadline, wcets, **kw):
    from apps.realtime.models import RealTime, RealTimeWcet

    row = RealTime.objects.create(
        cluster=cluster, namespace=cluster.namespace, name=name, criticality=criticality, period=period,
        deadline=deadline, **kw,
    )  # fmt: skip
    nodes = {n.name: n for n in cluster.nodes.all()}
    for i, (node, w) in enumerate(wcets.items()):
        RealTimeWcet.objects.create(realtime=row, node=nodes[node], wcet=w, position=i)
    return row


def make_pod(cluster, name, node, criticality="NONE", stateless=False, cpu=0.0, memory_mib=0.0, realtime=None,
             utilization=None, container=None):  # fmt: skip
    from apps.realtime.models import RTPod

    return RTPod.objects.create(
        cluster=cluster, namespace=cluster.namespace, name=name, uid=f"uid-{name}", node=node,
        container_name=container or name, criticality=criticality, stateless=stateless, cpu=cpu,
        memory_mib=memory_mib, realtime=realtime, utilization=utilization, scheduler_name="RT-scheduler",
    )  # fmt: skip


@pytest.fixture
def rt_cluster(cluster):
    """The conftest's 4-node cluster (model only) with RT attributes on its nodes."""
    for node in cluster.nodes.all():
        crit, rt = RT_NODES[node.name]
        node.rt, node.criticality = rt, crit
        node.save()
    return cluster


@pytest.fixture
def node0_pods(rt_cluster):
    """On node0: a B violator and candidates of every kind (only stateless, lower-class, non-C ones qualify)."""
    return {
        "slam": make_pod(rt_cluster, "slam", "node0", "B", True, cpu=1, utilization=0.4),
        "lidar": make_pod(rt_cluster, "lidar", "node0", "A", True, cpu=0.5, memory_mib=2000, utilization=0.12),
        "planner": make_pod(rt_cluster, "planner", "node0", "A", True, cpu=1.5, memory_mib=100, utilization=0.3),
        "logger": make_pod(rt_cluster, "logger", "node0", "NONE", False, cpu=2),
        "arm": make_pod(rt_cluster, "arm", "node0", "A", False, cpu=3, utilization=0.5),
        "other": make_pod(rt_cluster, "other", "node1", "NONE", True, cpu=3),
    }
