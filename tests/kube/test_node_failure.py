"""A hollow node that dies mid-run, end to end on the session's real multi-node cluster (issue 12): Continuum
pushes a HEFT4K schedule whose pods run on three hollow nodes; the kubemark process of one of them is killed;
nobody writes the node's status: the real node lifecycle controller turns it NotReady (Unknown), taints it
``node.kubernetes.io/unreachable`` and, once the pods' 10 s tolerations (devcluster.EVICTION_SECONDS, set on the
apiserver) run out, evicts its pods; then the HEFT4K watcher (apps/heft4k/watch.py) sees the node down and
remaps ONLY the tasks that were there: every other task keeps its node and its very pod.

Runs right after test_multinode.py (conftest.FIRST): the v1.20 node lifecycle controller stops tainting dead
nodes NoExecute once a test deleted a NotReady synthetic node. The dedicated node (LOST_NODE) is restarted at
the end, so the session's later tests find it Ready.
"""

import signal

import pytest

from apps.heft4k.models import RemapEvent
from apps.heft4k.watch import watch_nodes
from continuum.engine.heft4k.remap import remap as engine_remap
from tests.heft4k.fan import heft4k_schedule, run
from tests.kube.conftest import LOST_NODE, running_on, wait_for

pytestmark = [pytest.mark.kube, pytest.mark.django_db]

#: Decides partial vs total remap; high enough that losing a node of workers is a partial remap (the lost node
#: never holds the critical sink: HEFT4K puts it with the source on the first node, see tests/heft4k/fan.py).
THRESHOLD = 0.9
NODES = ("hollow-a", "hollow-b", LOST_NODE)


def ready(node) -> str:
    return next((c.status for c in node.status.conditions or [] if c.type == "Ready"), "Unknown")


def taints(node) -> set[tuple[str, str]]:
    return {(t.key, t.effect) for t in node.spec.taints or []}


def snapshot(kube, namespace: str) -> dict:
    """pod name -> (uid, node, phase, being deleted)."""
    return {
        p.metadata.name: (p.metadata.uid, p.spec.node_name, p.status.phase, p.metadata.deletion_timestamp is not None)
        for p in kube.list_namespaced_pod(namespace).items
    }


def test_a_dead_hollow_node_is_evicted_by_the_controller_and_only_its_tasks_are_remapped(
    api, kube, kube_multinode, hollow_cluster, kube_namespace
):
    # The boards HEFT4K plans for are declared with 4 CPUs each (the planning input); pushed pods carry no
    # requests, so each hollow node (1 CPU) runs all it gets.
    cluster = hollow_cluster([{"name": n, "cpu": 4, "memory_mib": 8192} for n in NODES], name="edge-live")
    schedule = heft4k_schedule(api, cluster)
    job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert job["state"] == "succeeded", job
    chosen = {a.pod_name: a.processor for a in schedule.assignments.all()}
    assert set(chosen.values()) == set(NODES)  # HEFT4K used every node, the one that will die too
    # What an operator sees: every pod Running on the node Continuum chose.
    wait_for("every pushed pod Running on its node", lambda: running_on(kube, kube_namespace) == chosen)
    before = snapshot(kube, kube_namespace)
    rows = {a.task: a for a in schedule.assignments.all()}
    lost = sorted(t for t, a in rows.items() if a.processor == LOST_NODE)
    kept = sorted(t for t in rows if t not in lost)
    assert lost and "sink" in kept and "src" in kept
    truth = engine_remap(
        schedule.to_engine(), schedule.application.graph, schedule.engine_platform(), [LOST_NODE], threshold=THRESHOLD
    )
    assert truth.mode == "partial"

    try:
        kube_multinode.stop_process(f"node/{LOST_NODE}", signal.SIGKILL)
        assert not kube_multinode.running()[f"node/{LOST_NODE}"]

        # The node lifecycle controller notices the silence on its own ...
        node = wait_for(
            "the dead node NotReady and tainted unreachable:NoExecute",
            lambda: (
                (n := kube.read_node(LOST_NODE))
                and ready(n) != "True"
                and ("node.kubernetes.io/unreachable", "NoExecute") in taints(n)
                and n
            ),
        )
        assert ready(node) == "Unknown"  # the kubelet stopped posting status
        # ... and its taint manager evicts the dead node's pods once their tolerations run out (the dead kubelet
        # cannot confirm, so they stay Terminating); the other nodes' pods are untouched.
        lost_pods = {rows[t].pod_name for t in lost}
        wait_for(
            "the dead node's pods evicted by the controller",
            lambda: all(snapshot(kube, kube_namespace)[name][3] for name in lost_pods),
        )
        now = snapshot(kube, kube_namespace)
        assert all(now[rows[t].pod_name] == before[rows[t].pod_name] for t in kept)

        # The HEFT4K watcher sees the node down and remaps the schedule: the lost tasks only.
        report = watch_nodes(cluster, timeout=5, threshold=THRESHOLD)
        assert {"node": LOST_NODE, "status": "Unknown", "was": "Ready"} in report.changes
        assert [r["state"] for r in report.remaps] == ["succeeded"], report.remaps
        event = RemapEvent.objects.get(pk=report.remaps[0]["remap"])
        assert (event.trigger, event.status, event.decision) == ("watch", "applied", "partial")
        assert event.failed_nodes == [LOST_NODE]
        assert sorted(event.lost_tasks) == lost == sorted(event.moved_tasks) == sorted(event.changed_tasks)
        new_rows = {a.task: a for a in event.new_schedule.assignments.all()}
        for task in kept:  # same node, same pod (uid), not touched by the remap
            assert new_rows[task].processor == rows[task].processor
            assert new_rows[task].pod_name == rows[task].pod_name
        for task in lost:
            assert new_rows[task].processor in NODES and new_rows[task].processor != LOST_NODE
        # The replacements run on the live nodes Continuum chose; the kept pods still run where they were.
        expected = {a.pod_name: a.processor for a in new_rows.values()}
        wait_for("the remapped schedule's pods Running", lambda: running_on(kube, kube_namespace) == expected)
        after = snapshot(kube, kube_namespace)
        assert all(after[rows[t].pod_name][0] == before[rows[t].pod_name][0] for t in kept)
        assert not lost_pods & set(after)  # force-deleted: no kubelet was left to confirm
    finally:
        # The session's later tests find the node as they expect it: Ready, untainted.
        if not kube_multinode.running()[f"node/{LOST_NODE}"]:
            kube_multinode.restart_node(LOST_NODE, timeout=300)
    assert ready(kube.read_node(LOST_NODE)) == "True"
