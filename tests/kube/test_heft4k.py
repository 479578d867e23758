"""HEFT4K against the session's real multi-node cluster: niceness in the pods, the node watcher and remaps that
recreate only the pods that change. The niceness test pushes to hollow nodes, where the pods run. The remap tests
fail, delete or cordon nodes, so they use synthetic Node objects (``make_node``: their Leases are renewed, so the
real node lifecycle controller keeps the Ready condition a test writes and taints the node as it would a real
one; no kubelet: pods stay Pending once bound); a hollow node killed for real, its pods evicted by the
controller-manager and remapped by the watcher, is test_node_failure.py."""

import json
from io import StringIO

import pytest
from django.conf import settings

from apps.heft4k.models import RemapEvent
from apps.heft4k.watch import watch_nodes
from continuum.engine.heft4k.remap import remap as engine_remap
from tests.heft4k.fan import heft4k_schedule, run
from tests.kube.conftest import running_on, wait_for
from tests.kubeapi import free_port, kubeconfig_text

pytestmark = [pytest.mark.kube, pytest.mark.django_db]


def pods(kube, namespace: str) -> dict:
    return {p.metadata.name: p for p in kube.list_namespaced_pod(namespace).items}


def pushed_schedule(api, kube_cluster, **params):
    schedule = heft4k_schedule(api, kube_cluster, **params)
    job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert job["state"] == "succeeded", job
    return schedule


def snapshot(kube, namespace: str) -> dict:
    """pod name -> (uid, resourceVersion, node)."""
    return {
        name: (p.metadata.uid, p.metadata.resource_version, p.spec.node_name)
        for name, p in pods(kube, namespace).items()
    }


def test_pods_run_their_command_under_nice_with_sys_nice_only_when_negative(api, kube, hollow_cluster, kube_namespace):
    # Three hollow nodes declared as the 4-CPU boards HEFT4K plans for (the pods carry no requests).
    cluster = hollow_cluster([{"name": n, "cpu": 4, "memory_mib": 8192} for n in ("hollow-a", "hollow-b", "hollow-c")])
    schedule = pushed_schedule(api, cluster, nice_high=-5, nice_low=10)
    chosen = {a.pod_name: a.processor for a in schedule.assignments.all()}
    wait_for("every pod Running on its node", lambda: running_on(kube, kube_namespace) == chosen)
    live = pods(kube, kube_namespace)
    assert len(live) == schedule.assignments.count() == 22
    seen = set()
    for a in schedule.assignments.all():
        container = live[a.pod_name].spec.containers[0]
        assert container.command == [
            settings.CONTINUUM_NICE_BINARY,
            "-n",
            str(a.niceness),
            "--",
            *settings.CONTINUUM_POD_COMMAND,
        ]
        assert live[a.pod_name].metadata.annotations["continuum.io/niceness"] == str(a.niceness)
        added = (
            container.security_context.capabilities.add
            if container.security_context and container.security_context.capabilities
            else None
        )
        assert added == (["SYS_NICE"] if a.niceness < 0 else None), (a.task, a.niceness)
        seen.add(a.niceness < 0)
    assert seen == {True, False}  # both kinds were pushed
    assert schedule.assignments.get(task="src").niceness == -5  # the top-ranked task gets nice_high


def test_the_watcher_remaps_a_not_ready_node_and_recreates_only_the_lost_pods(api, kube, kube_cluster, kube_namespace):
    schedule = pushed_schedule(api, kube_cluster)
    before = snapshot(kube, kube_namespace)
    old_rows = {a.task: a for a in schedule.assignments.all()}
    lost = sorted(t for t, a in old_rows.items() if a.processor == "node1")
    assert len(lost) == 4
    truth = engine_remap(
        schedule.to_engine(), schedule.application.graph, schedule.engine_platform(), ["node1"], threshold=0.2
    )
    kube.patch_node_status("node1", {"status": {"conditions": [{"type": "Ready", "status": "False"}]}})

    report = watch_nodes(kube_cluster, timeout=2)

    assert report.changes == [{"node": "node1", "status": "NotReady", "was": "Ready"}]
    assert kube_cluster.nodes.get(name="node1").status == "NotReady"
    assert len(report.remaps) == 1 and report.remaps[0]["state"] == "succeeded", report.remaps
    event = RemapEvent.objects.get(pk=report.remaps[0]["remap"])
    assert (event.trigger, event.status, event.schedule_id) == ("watch", "applied", schedule.pk)
    assert event.decision == truth.mode == "partial"
    assert sorted(event.lost_tasks) == lost == sorted(event.moved_tasks) and event.reniced_tasks == []
    assert event.makespan_after == pytest.approx(truth.makespan_after)
    assert event.pods_moved == 4 and event.push_ms > 0
    assert event.message == "4 pods recreated, 18 kept"

    after = snapshot(kube, kube_namespace)
    new_rows = {a.task: a for a in event.new_schedule.assignments.all()}
    for task, row in old_rows.items():
        if task in lost:
            assert row.pod_name not in after  # force-deleted: its kubelet is gone
            new = new_rows[task]
            assert new.processor != "node1" and new.placement == "bound"
            assert after[new.pod_name][2] == new.processor  # re-bound elsewhere
            assert new.pod_name not in before
        else:
            assert after[row.pod_name] == before[row.pod_name]  # same uid, resourceVersion and node
            assert new_rows[task].pod_name == row.pod_name and new_rows[task].placement == "bound"
    assert len(after) == len(before)
    # The old schedule says where its pods went; the new one is now the latest pushed schedule.
    for task in lost:
        old = schedule.assignments.get(task=task)
        assert old.placement == "not_pushed"
        assert (
            old.placement_message
            == f"pod deleted by remap {event.pk}: the task runs in schedule {event.new_schedule_id}"
        )

    # Pushing the remapped schedule again changes nothing (its kept pods belong to the old schedule).
    assert run(api, f"/api/v1/schedules/{event.new_schedule_id}/push/")["state"] == "succeeded"
    assert snapshot(kube, kube_namespace) == after
    # Watching again does not remap the same failure twice.
    again = watch_nodes(kube_cluster, timeout=1)
    assert again.changes == [] and again.remaps == []
    assert RemapEvent.objects.count() == 1


def test_a_node_deleted_while_watching_arrives_as_a_watch_event(api, kube, kube_cluster, kube_namespace):
    schedule = pushed_schedule(api, kube_cluster)
    before = snapshot(kube, kube_namespace)
    lost = {a.task: a.pod_name for a in schedule.assignments.filter(processor="node3")}

    def fail_node(report):
        kube.delete_node("node3")  # after the list: only the watch stream can tell

    report = watch_nodes(kube_cluster, timeout=3, on_listed=fail_node)
    assert report.lists == 1 and report.events >= 1
    assert report.changes == [{"node": "node3", "status": "NotReady", "was": "Ready"}]
    event = RemapEvent.objects.get()
    assert event.failed_nodes == ["node3"] and sorted(event.lost_tasks) == sorted(lost)
    assert event.status == "applied" and event.decision in ("partial", "total")
    after = snapshot(kube, kube_namespace)
    changed = set(event.changed_tasks)
    assert changed >= set(lost)
    kept = [a for a in schedule.assignments.all() if a.task not in changed]
    assert kept and all(after[a.pod_name] == before[a.pod_name] for a in kept)
    for a in event.new_schedule.assignments.filter(task__in=changed):
        assert after[a.pod_name][2] == a.processor != "node3"


def test_what_if_changes_no_pod_then_apply_recreates_only_the_changed_ones(api, kube, kube_cluster, kube_namespace):
    schedule = pushed_schedule(api, kube_cluster)
    before = snapshot(kube, kube_namespace)
    job = run(api, f"/api/v1/schedules/{schedule.pk}/remap/", {"fail": ["node2"], "what_if": True})
    assert job["state"] == "succeeded", job
    event = RemapEvent.objects.get()
    assert event.status == "what-if" and event.decision == "partial"
    assert snapshot(kube, kube_namespace) == before  # a what-if touches nothing
    assert kube_cluster.nodes.get(name="node2").status == "Ready"

    job = run(api, f"/api/v1/remaps/{event.pk}/apply/")
    assert job["state"] == "succeeded", job
    event.refresh_from_db()
    assert event.status == "applied"
    # node2 is alive here: the moved pods are deleted gracefully (they stay Terminating without a kubelet).
    after = pods(kube, kube_namespace)
    moved = {a.task: a.pod_name for a in schedule.assignments.filter(task__in=event.moved_tasks)}
    assert all(after[name].metadata.deletion_timestamp is not None for name in moved.values())
    for a in event.new_schedule.assignments.all():
        if a.task in moved:
            assert after[a.pod_name].spec.node_name == a.processor != "node2"
        else:
            assert (after[a.pod_name].metadata.uid, after[a.pod_name].metadata.resource_version) == before[a.pod_name][
                :2
            ]
    # Applying twice is refused; the job records why.
    assert api.post(f"/api/v1/remaps/{event.pk}/apply/").status_code == 400


def test_a_refused_placement_fails_the_remap_and_is_recorded(api, kube, kube_cluster, kube_namespace):
    schedule = pushed_schedule(api, kube_cluster)
    # Every other node is cordoned in Kubernetes but still Ready in Continuum: the new pods cannot be bound.
    for name in ("node0", "node2", "node3"):
        kube.patch_node(name, {"spec": {"unschedulable": True}})
    job = run(api, f"/api/v1/schedules/{schedule.pk}/remap/", {"fail": ["node1"]})
    assert job["state"] == "failed"
    event = RemapEvent.objects.get()
    assert event.status == "failed" and "is cordoned (unschedulable)" in event.message
    assert f"remap {event.pk}: 4 of 4 pods could not be placed" in job["error"]
    assert {p["created"] for p in event.pods} == {False}
    assert api.get(f"/api/v1/remaps/{event.pk}/").data["can_apply"] is True  # a retry is allowed
    for name in ("node0", "node2", "node3"):
        kube.patch_node(name, {"spec": {"unschedulable": False}})
    job = run(api, f"/api/v1/remaps/{event.pk}/apply/")
    assert job["state"] == "succeeded", job
    event.refresh_from_db()
    assert event.status == "applied" and event.pods_moved == 4


def test_the_watcher_gives_up_after_bounded_reconnects(kube_admin, api, cluster, kube_server):
    from apps.kube.gateway import KubeError

    closed = kubeconfig_text(f"https://127.0.0.1:{free_port()}", "token", kube_server.ca_path.read_bytes())
    assert kube_admin.patch(f"/api/v1/clusters/{cluster.pk}/", {"kubeconfig": closed}, format="json").status_code == 200
    cluster.refresh_from_db()
    waits = []
    with pytest.raises(KubeError, match="node watch gave up after 2 reconnects: Kubernetes API unreachable"):
        watch_nodes(cluster, timeout=30, retries=2, backoff=0.5, sleep=waits.append)
    assert waits == [0.5, 1.0]  # exponential backoff, bounded
    assert not cluster.nodes.exclude(status="Ready").exists()


def test_heft4k_watch_command(api, kube, kube_cluster, kube_namespace):
    from django.core.management import call_command

    pushed_schedule(api, kube_cluster)
    kube.patch_node_status("node2", {"status": {"conditions": [{"type": "Ready", "status": "Unknown"}]}})
    out = StringIO()
    call_command("heft4k_watch", "--cluster", str(kube_cluster.pk), "--timeout", "1", "--json", stdout=out)
    result = json.loads(out.getvalue())
    assert result["changes"] == [{"node": "node2", "status": "Unknown", "was": "Ready"}]
    assert [r["state"] for r in result["remaps"]] == ["succeeded"]
    assert RemapEvent.objects.get().failed_nodes == ["node2"]
