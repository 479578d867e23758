"""Live pod state (issue 12): ``watch_cluster`` follows a cluster's pods and pod Events and stores each pod's
phase, node and newest event on the rows of the apps that own the pod (apps/clusters/live.py).

First the dispatch, fed with watch events as the server's JSON (no cluster): which handler gets what, the
newest event wins, a replay writes nothing. Then on the real multi-node cluster: a pushed schedule's pods
reach Running on the assigned hollow node and the API shows it with the kubelet's last event."""

from __future__ import annotations

import time

import pytest
from django.core.management import call_command

from apps.clusters.live import LiveState, pod_handlers, register_pod_handler, store
from apps.kube.gateway import PREFIX, PodEvent, event_of, pod_state

#: Generous: the suite runs on a busy 2-core machine. Tests wait for conditions, never for fixed times.
TIMEOUT = 180


def pod(name, *, ns="ns", uid=None, phase="Pending", node="", labels=None, deleting=False):
    meta = {"name": name, "namespace": ns, "uid": uid or f"uid-{name}", "labels": labels or {},
            "creationTimestamp": "2026-11-24T01:00:00Z", "resourceVersion": "1"}  # fmt: skip
    if deleting:
        meta["deletionTimestamp"] = "2026-11-24T01:05:00Z"
    spec = {"nodeName": node} if node else {}
    return {"metadata": meta, "spec": spec, "status": {"phase": phase}}


def event(pod_name, reason, message="", *, at="2026-11-24T01:00:01Z", ns="ns", uid=None, kind="Pod"):
    return {
        "metadata": {"name": f"{pod_name}.{reason}", "namespace": ns, "resourceVersion": "2"},
        "involvedObject": {"kind": kind, "namespace": ns, "name": pod_name, "uid": uid or f"uid-{pod_name}"},
        "reason": reason, "message": message, "lastTimestamp": at, "type": "Normal",
    }  # fmt: skip


def w(kind, obj):
    return {"type": kind, "raw_object": obj, "object": obj}


# -- the gateway's plain data ------------------------------------------------------------------------------------


def test_a_pods_json_becomes_its_state_and_an_event_about_a_pod_is_recognised():
    state = pod_state(pod("p", phase="Running", node="hollow-a", labels={"app": "x"}, deleting=True))
    assert (state.namespace, state.name, state.phase, state.node, state.terminating) == (
        "ns", "p", "Running", "hollow-a", True)  # fmt: skip
    assert pod_state(pod("p"), deleted=True).phase == "Deleted"
    key, uid, ev = event_of(event("p", "Started", "Started container task"))
    assert (key, uid, ev.text()) == (("ns", "p"), "uid-p", "Started: Started container task")
    assert event_of(event("n", "NodeReady", kind="Node")) is None
    # eventTime (events.k8s.io style) with microseconds compares with lastTimestamp by instant, not as text
    later = PodEvent("Started", "", at="2026-11-24T01:00:01.500000Z")
    assert later.newer_than(PodEvent("Pulled", "", at="2026-11-24T01:00:01Z"))
    assert not PodEvent("Pulled", "", at="2026-11-24T01:00:01Z").newer_than(later)


# -- the dispatch (no cluster, no database) ------------------------------------------------------------------------


def recording():
    seen = []

    def handler(cluster, state):
        seen.append((state.name, state.phase, state.node, state.event.reason if state.event else ""))
        return 1

    return seen, handler


def test_dispatch_hands_each_change_to_the_handlers_once_with_the_newest_event():
    seen, handler = recording()
    live = LiveState(cluster=None, handlers={"rec": handler})
    assert live.on_event(w("ADDED", event("p", "Scheduled", at="2026-11-24T01:00:00Z"))) == 0  # pod not seen yet
    assert live.on_pod(w("ADDED", pod("p"))) == 1  # the held event comes with the pod
    assert seen == [("p", "Pending", "", "Scheduled")]
    live.on_pod(w("MODIFIED", pod("p", node="hollow-a")))
    live.on_event(w("ADDED", event("p", "Started", at="2026-11-24T01:00:05Z")))
    live.on_event(w("ADDED", event("p", "Pulled", at="2026-11-24T01:00:03Z")))  # older: ignored
    live.on_pod(w("MODIFIED", pod("p", node="hollow-a", phase="Running")))
    assert seen[1:] == [
        ("p", "Pending", "hollow-a", "Scheduled"),
        ("p", "Pending", "hollow-a", "Started"),
        ("p", "Running", "hollow-a", "Started"),
    ]
    # a replay (a relist, a resumed watch) with nothing new dispatches nothing
    live.on_pod(w("MODIFIED", pod("p", node="hollow-a", phase="Running")))
    live.on_event(w("MODIFIED", event("p", "Started", at="2026-11-24T01:00:05Z")))
    assert len(seen) == 4
    live.on_pod(w("DELETED", pod("p", node="hollow-a", phase="Running")))
    assert seen[-1] == ("p", "Deleted", "hollow-a", "Started")
    assert live.pods == {}
    # a pod of the same name but another uid starts afresh: the old pod's events are not its own
    live.on_pod(w("ADDED", pod("p", uid="uid-2")))
    assert seen[-1] == ("p", "Pending", "", "")
    assert live.on_event(w("ADDED", event("p", "Killing", at="2026-11-24T02:00:00Z"))) == 0  # old uid
    assert live.report()["updated"] == {"rec": 6}


def test_a_failing_handler_does_not_stop_the_others():
    seen, handler = recording()

    def broken(cluster, state):
        raise RuntimeError("bug")

    live = LiveState(cluster=None, handlers={"broken": broken, "rec": handler})
    live.on_pod(w("ADDED", pod("p")))
    assert seen == [("p", "Pending", "", "")]


def test_the_owning_apps_registered_their_handlers():
    assert {"scheduling", "containers", "realtime"} <= set(pod_handlers())
    register_pod_handler("scheduling", pod_handlers()["scheduling"])  # by name: replacing keeps one
    assert list(pod_handlers()).count("scheduling") == 1


# -- the handlers on stored rows (database, no cluster) -------------------------------------------------------------


@pytest.fixture
def owned(cluster, schedule):
    """An assignment pushed as pod ``sched-pod``, a container deployed as ``web-dep`` and an RT pod ``rt-pod``."""
    from apps.containers.models import ContainerDeployment, Placement
    from apps.realtime.models import RTPod

    schedule.cluster = cluster
    schedule.save(update_fields=["cluster"])
    cluster.namespace = "ns"  # the namespace Continuum owns on this cluster: where its pods are
    cluster.save(update_fields=["namespace"])
    assignment = schedule.assignments.first()
    assignment.pod_name = "sched-pod"
    assignment.save(update_fields=["pod_name"])
    placement = Placement.objects.create(
        fleet=cluster.fleet, cluster=cluster, policy="test", containers={}, cluster_document={},
        plan={"decisions": []},
        inter_node_bandwidth=0.0,
    )  # fmt: skip
    deployment = ContainerDeployment.objects.create(
        placement=placement, container="web", node="n1", deployment="web-dep", namespace="ns", state="applied"
    )
    rt = RTPod.objects.create(cluster=cluster, namespace="ns", name="rt-pod", uid="uid-rt-pod", node="n1")
    return assignment, deployment, rt


def sched_labels(assignment):
    return {f"{PREFIX}/schedule": str(assignment.schedule_id), f"{PREFIX}/application": str(
        assignment.schedule.application_id)}  # fmt: skip


@pytest.mark.django_db
def test_the_handlers_store_phase_node_and_event_on_their_rows_and_a_replay_writes_nothing(
    owned, cluster, django_assert_num_queries
):
    assignment, deployment, rt = owned
    live = LiveState(cluster)
    stream = [
        ("pod", w("ADDED", pod("sched-pod", phase="Running", node="n1", labels=sched_labels(assignment)))),
        ("event", w("ADDED", event("sched-pod", "Started", "Started container task"))),
        ("pod", w("ADDED", pod("web-dep-1", labels={f"{PREFIX}/deployment": "web-dep"}))),
        ("pod", w("MODIFIED", pod("web-dep-1", phase="Running", node="n1", labels={f"{PREFIX}/deployment": "web-dep"}))),  # noqa: E501
        ("event", w("ADDED", event("web-dep-1", "Pulled", "image present"))),
        ("pod", w("ADDED", pod("rt-pod", phase="Running", node="n1"))),
        ("event", w("ADDED", event("rt-pod", "Started"))),
        ("pod", w("ADDED", pod("stranger", phase="Running", node="n1"))),  # nobody's: no row anywhere
    ]  # fmt: skip
    for kind, payload in stream:
        (live.on_pod if kind == "pod" else live.on_event)(payload)
    assignment.refresh_from_db()
    deployment.refresh_from_db()
    rt.refresh_from_db()
    assert (assignment.pod_phase, assignment.pod_node, assignment.pod_event) == (
        "Running", "n1", "Started: Started container task")  # fmt: skip
    assert assignment.pod_state_at is not None
    assert (deployment.pod_name, deployment.pod_phase, deployment.pod_node, deployment.pod_event) == (
        "web-dep-1", "Running", "n1", "Pulled: image present")  # fmt: skip
    assert (rt.phase, rt.node, rt.pod_event) == ("Running", "n1", "Started")
    assert live.report()["updated"] == {"containers": 3, "realtime": 2, "scheduling": 2}

    # A watcher restarting (a fresh dispatcher) gets every pod's current state and the Events again, from two
    # watches in either order: the UPDATEs match no row.
    at = assignment.pod_state_at
    labels = {f"{PREFIX}/deployment": "web-dep"}
    pods = [
        w("ADDED", pod("sched-pod", phase="Running", node="n1", labels=sched_labels(assignment))),
        w("ADDED", pod("web-dep-1", phase="Running", node="n1", labels=labels)),
        w("ADDED", pod("rt-pod", phase="Running", node="n1")),
        w("ADDED", pod("stranger", phase="Running", node="n1")),
    ]
    events = [payload for kind, payload in stream if kind == "event"]
    for first_pods in (True, False):
        replay = LiveState(cluster)
        for payload in pods if first_pods else []:
            replay.on_pod(payload)
        for payload in events:
            replay.on_event(payload)
        for payload in [] if first_pods else pods:
            replay.on_pod(payload)
        assert replay.report()["updated"] == {}
    assignment.refresh_from_db()
    assert assignment.pod_state_at == at
    # Unchanged rows cost one UPDATE (of nothing), not a read and a write.
    with django_assert_num_queries(1):
        assert store(type(assignment).objects.filter(pk=assignment.pk), {"pod_phase": "Running"}) == 0


@pytest.mark.django_db
def test_a_deployment_shows_its_newest_pod_while_the_old_one_goes(owned, cluster):
    _, deployment, _ = owned
    labels = {f"{PREFIX}/deployment": "web-dep"}
    live = LiveState(cluster)
    live.on_pod(w("ADDED", pod("web-dep-old", phase="Running", node="n1", labels=labels)))
    live.on_pod(w("ADDED", pod("web-dep-new", labels=labels)))  # Recreate: the new pod replaces the shown one
    live.on_pod(w("MODIFIED", pod("web-dep-old", phase="Running", node="n1", labels=labels, deleting=True)))
    live.on_pod(w("DELETED", pod("web-dep-old", phase="Running", node="n1", labels=labels, deleting=True)))
    live.on_event(w("ADDED", event("web-dep-old", "Killing", "Stopping container ros")))
    deployment.refresh_from_db()
    assert (deployment.pod_name, deployment.pod_phase, deployment.pod_event) == ("web-dep-new", "Pending", "")
    live.on_pod(w("MODIFIED", pod("web-dep-new", phase="Running", node="n2", labels=labels)))
    deployment.refresh_from_db()
    assert (deployment.pod_name, deployment.pod_phase, deployment.pod_node) == ("web-dep-new", "Running", "n2")


@pytest.mark.django_db
def test_the_api_shows_the_live_state_read_only(api, owned):
    assignment, deployment, rt = owned
    LiveState(assignment.schedule.cluster).on_pod(
        w("ADDED", pod("sched-pod", phase="Running", node="n1", labels=sched_labels(assignment)))
    )
    data = api.get(f"/api/v1/schedules/{assignment.schedule_id}/").data
    row = next(a for a in data["assignments"] if a["pod_name"] == "sched-pod")
    assert (row["pod_phase"], row["pod_node"], row["pod_event"]) == ("Running", "n1", "")
    assert row["pod_state_at"]
    placement = api.get(f"/api/v1/placements/{deployment.placement_id}/").data
    assert {"pod_name", "pod_phase", "pod_node", "pod_event", "pod_state_at"} <= set(placement["deployments"][0])
    assert {"phase", "pod_event", "pod_state_at"} <= set(api.get(f"/api/v1/rt-pods/{rt.pk}/").data)


@pytest.mark.django_db
def test_the_command_refuses_an_unknown_or_model_only_cluster(cluster):
    from django.core.management.base import CommandError

    with pytest.raises(CommandError, match="does not exist") as refused:
        call_command("watch_cluster", "no-such-cluster")
    assert refused.value.returncode == 2  # bad input, as every command
    with pytest.raises(CommandError, match="model-only"):
        call_command("watch_cluster", str(cluster.pk), "--max-seconds", "1")
    with pytest.raises(CommandError, match="model-only"):
        call_command("watch_cluster", cluster.name)


@pytest.mark.django_db
def test_a_nodes_ready_status_reaches_its_compute_node_once(cluster):
    node = cluster.nodes.first()
    live = LiveState(cluster)

    def node_event(kind, ready):
        obj = {"metadata": {"name": node.name}, "status": {"conditions": [{"type": "Ready", "status": ready}]}}
        return w(kind, obj)

    assert live.on_node(node_event("MODIFIED", "False")) == 1
    assert live.on_node(node_event("MODIFIED", "False")) == 0  # unchanged: nothing written
    node.refresh_from_db()
    assert node.status == "NotReady"
    assert live.on_node(node_event("MODIFIED", "True")) == 1
    assert live.on_node(node_event("DELETED", "True")) == 1  # gone from the API: NotReady, the row is kept
    node.refresh_from_db()
    assert node.status == "NotReady"
    assert live.on_node(w("ADDED", {"metadata": {"name": "unknown"}, "status": {}})) == 0  # not created


# -- on the real multi-node cluster -------------------------------------------------------------------------------


@pytest.mark.kube
@pytest.mark.django_db
def test_a_pushed_schedules_pods_show_running_on_their_node_with_the_kubelets_event(
    api, kube_admin, kube_multinode, kube_namespace
):
    from apps.scheduling.models import Schedule

    nodes = [{"name": name, "cpu": 1, "memory_mib": 3840} for name in ("hollow-a", "hollow-b")]
    namespace = kube_namespace  # deleted at the end: the hollow nodes are shared by the session
    doc = {"name": "hollow-live", "kubeconfig": kube_multinode.kubeconfig(), "format": "continuum.cluster/v1",
           "nodes": nodes, "links": [{"src": "hollow-a", "dst": "hollow-b", "bandwidth_mbps": 1000}]}  # fmt: skip
    response = kube_admin.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 201, response.data
    cluster_id = response.data["id"]
    response = api.patch(f"/api/v1/clusters/{cluster_id}/", {"namespace": namespace}, format="json")
    assert response.status_code == 200, response.data
    dag = {
        "format": "continuum.dag/v1",
        "name": "fork",
        "tasks": [{"id": "src", "cost": {"cpu": 2}}, {"id": "left", "cost": {"cpu": 9}},
                  {"id": "right", "cost": {"cpu": 9}}],
        "edges": [{"src": "src", "dst": "left", "data": 0.0}, {"src": "src", "dst": "right", "data": 0.0}],
    }  # fmt: skip
    response = api.post("/api/v1/applications/", {"name": "fork", "dag": dag}, format="json")
    assert response.status_code == 201, response.data
    response = api.post(f"/api/v1/applications/{response.data['id']}/schedule/", {"cluster": cluster_id}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded", job
    schedule = Schedule.objects.get(pk=job["result"]["schedule"])
    response = api.post(f"/api/v1/schedules/{schedule.pk}/push/", {}, format="json")
    assert response.status_code == 202, response.data
    assert api.get(f"/api/v1/jobs/{response.data['id']}/").data["state"] == "succeeded"

    def live():
        """One bounded run of the command (in this thread: it writes in the test's transaction), then the API."""
        call_command("watch_cluster", str(cluster_id), "--namespace", namespace, "--max-seconds", "4", "--json")
        rows = api.get(f"/api/v1/schedules/{schedule.pk}/").data["assignments"]
        done = all(r["pod_phase"] == "Running" and r["pod_node"] == r["processor"] and r["pod_event"] for r in rows)
        return rows if done else None

    deadline = time.monotonic() + TIMEOUT
    rows = None
    while rows is None and time.monotonic() < deadline:
        rows = live()
    last = api.get(f"/api/v1/schedules/{schedule.pk}/").data["assignments"]
    assert rows, f"the API never showed every pod Running on its node with an event: {last}"
    assert {r["processor"] for r in rows} == {"hollow-a", "hollow-b"}
    # What kubemark's kubelet reports for a pod it ran with its fake runtime.
    assert {r["pod_event"].split(":")[0] for r in rows} <= {"Scheduled", "Pulled", "Created", "Started"}
    assert all(r["pod_state_at"] for r in rows)
    # the node watch stored the hollow nodes' Ready status on the imported nodes
    assert dict(schedule.cluster.nodes.values_list("name", "status")) == {"hollow-a": "Ready", "hollow-b": "Ready"}


@pytest.mark.kube
@pytest.mark.django_db
def test_a_pushed_placements_deployments_show_their_pods_running_where_kube_scheduler_put_them(
    api, kube_admin, kube_multinode, kube_namespace
):
    from apps.containers.models import ContainerDeployment
    from tests.kube.conftest import MULTINODE_CLUSTER
    from tests.kube.test_ros_push import autoware_placement, run

    by_name = {n["name"]: n for n in MULTINODE_CLUSTER["nodes"]}
    nodes = [{"name": name, "arch": by_name[name]["arch"], "cpu": 1, "memory_mib": 3840, "labels": by_name[name].get(
        "labels", {})} for name in ("hollow-a", "hollow-b")]  # fmt: skip
    namespace = kube_namespace  # deleted at the end: the hollow nodes are shared by the session
    doc = {"name": "hollow-ros", "kubeconfig": kube_multinode.kubeconfig(), "format": "continuum.cluster/v1",
           "nodes": nodes, "links": [{"src": "hollow-a", "dst": "hollow-b", "bandwidth_mbps": 1000}]}  # fmt: skip
    response = kube_admin.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 201, response.data
    cluster_id = response.data["id"]
    response = api.patch(f"/api/v1/clusters/{cluster_id}/", {"namespace": namespace}, format="json")
    assert response.status_code == 200, response.data
    from apps.clusters.models import Cluster

    placement = autoware_placement(api, Cluster.objects.get(pk=cluster_id), cpu=0.2, extra={"overhead_mib": 0})
    job = run(api, f"/api/v1/placements/{placement.pk}/push/")
    assert job["state"] == "succeeded", job["error"]
    assert ContainerDeployment.objects.filter(placement=placement).count() == 4

    def live():
        call_command("watch_cluster", str(cluster_id), "--namespace", namespace, "--max-seconds", "4", "--json")
        rows = api.get(f"/api/v1/placements/{placement.pk}/").data["deployments"]
        done = all(r["pod_phase"] == "Running" and r["pod_node"] == r["node"] and r["pod_event"] for r in rows)
        return rows if done else None

    deadline = time.monotonic() + TIMEOUT
    rows = None
    while rows is None and time.monotonic() < deadline:
        rows = live()
    last = api.get(f"/api/v1/placements/{placement.pk}/").data["deployments"]
    assert rows, f"the API never showed every Deployment's pod Running on its node with an event: {last}"
    # kube-scheduler's own event for the pods it bound where the node selectors say
    assert all(r["pod_event"].startswith("Scheduled: Successfully assigned") for r in rows), rows
    assert all(r["pod_name"].startswith(r["deployment"]) for r in rows)


@pytest.mark.django_db
def test_a_pod_outside_the_clusters_namespace_cannot_spoof_a_schedules_state(owned, cluster):
    # Issue 25: anyone who may create pods somewhere can copy a schedule's labels and its pod's name; only the
    # pods of the namespace Continuum owns on this cluster are its pods.
    assignment, deployment, _rt = owned
    live = LiveState(cluster)
    spoof = pod(
        "sched-pod", ns="elsewhere", uid="uid-spoof", phase="Failed", node="evil", labels=sched_labels(assignment)
    )
    live.on_pod(w("ADDED", spoof))
    live.on_pod(
        w("ADDED", pod("web-dep-9", ns="elsewhere", phase="Failed", labels={f"{PREFIX}/deployment": "web-dep"}))
    )
    assignment.refresh_from_db()
    deployment.refresh_from_db()
    assert (assignment.pod_phase, assignment.pod_node) == ("", "")
    assert deployment.pod_name == "" and live.foreign == 2
    live.on_pod(w("ADDED", pod("sched-pod", phase="Running", node="n1", labels=sched_labels(assignment))))
    assignment.refresh_from_db()
    assert (assignment.pod_phase, assignment.pod_node) == ("Running", "n1")


@pytest.mark.django_db
def test_node_status_has_one_rule_and_unknown_is_not_ready(cluster):
    from apps.clusters.models import ComputeNode
    from apps.clusters.nodes import NOT_READY_Q, reconcile_nodes, status_of

    def node(name, status):
        return {"metadata": {"name": name}, "status": {"conditions": [{"type": "Ready", "status": status}]}}

    names = sorted(cluster.nodes.values_list("name", flat=True))
    assert status_of(node("x", "True")) == "Ready" and status_of(node("x", "False")) == "NotReady"
    assert status_of(node("x", "Unknown")) == "Unknown" and status_of({"metadata": {"name": "x"}}) == "Unknown"
    assert status_of(None) == "NotReady"  # gone from the API
    seen = []
    live = LiveState(cluster, {}, node_handlers={"rec": lambda c, changes, listed: seen.append((changes, listed))})
    listed = [node(names[0], "Unknown"), *(node(n, "True") for n in names[2:])]  # names[1] is gone
    assert live.on_node_list(listed) == 2
    rows = dict(cluster.nodes.values_list("name", "status"))
    assert rows[names[0]] == "Unknown" and rows[names[1]] == "NotReady"
    assert cluster.nodes.filter(NOT_READY_Q).count() == 2
    assert seen and seen[-1][1] is True and {c.node for c in seen[-1][0]} == set(names[:2])
    assert reconcile_nodes(cluster, listed) == []  # level-triggered: the same list changes nothing
    assert len(live.nodes) == len(listed)  # the agent's node informer
    live.on_node(w("MODIFIED", node(names[0], "True")))
    assert ComputeNode.objects.get(cluster=cluster, name=names[0]).status == "Ready"
    assert [(c.node, c.was, c.status) for c in seen[-1][0]] == [(names[0], "Unknown", "Ready")]


def test_heft4k_and_the_apps_register_with_the_agent_not_their_own_watches():
    from apps.clusters.nodes import node_handlers

    assert "heft4k-remap" in node_handlers()
    assert {"scheduling", "containers", "realtime"} <= set(pod_handlers())
