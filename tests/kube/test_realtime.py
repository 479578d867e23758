"""RT-Kube against the session's real multi-node cluster. The cluster's nodes are synthetic Node objects
(``make_node``, kept alive for the node lifecycle controller by their Leases; no kubelet: pods stay Pending once
bound); the session's hollow nodes are in the API too, and the RT scheduler weighs them.

The done criterion of the RT-Kube issue: RealTime objects created on both sides, pods bound by the RT
scheduler process (running in a thread), a missed-deadline report, the eviction, the node taint, the
re-binding of the evicted pod on another node, and the taint lifted when its time is up.
"""

import io
import threading
import time
from datetime import UTC, datetime, timedelta

import pytest
import yaml
from kubernetes import client, config

from apps.jobs.models import Job
from apps.realtime.models import Monitoring, MonitoringReport, NodeTaint, RealTime, RTDecision, RTEvent, RTPolicy
from apps.realtime.scheduler import RTScheduler
from tests.kube.conftest import SESSION_NODES
from tests.kubeapi import free_port, kubeconfig_text
from tests.realtime.conftest import RT_NODES

pytestmark = [pytest.mark.kube, pytest.mark.django_db(transaction=True)]
RT = ("rt.scheduling", "v1", "realtimes")
MON = ("rt.monitoring", "v1alpha1", "monitorings")
RT_TOLERATION = {"key": "RealTime", "operator": "Equal", "value": "RT", "effect": "NoSchedule"}


def wait_for(predicate, what: str, timeout: float = 120.0):  # generous: a busy 2-core machine
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"timed out after {timeout:g} s waiting for {what}")


@pytest.fixture
def custom(kubeconfig):
    api_client = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False)
    with api_client:
        yield client.CustomObjectsApi(api_client)


@pytest.fixture
def rt_kube_cluster(kube_cluster, api):
    for node in kube_cluster.nodes.all():
        node.criticality, node.rt = RT_NODES[node.name]
        node.save()
    RTPolicy.objects.create(cluster=kube_cluster, taint_duration_s=4)
    response = api.post("/api/v1/realtimes/sync/", {"cluster": kube_cluster.pk}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded", job
    assert sorted(job["result"]["nodes"]["tainted"]) == ["node0", "node1", "node2"]
    return kube_cluster


@pytest.fixture
def scheduler(rt_kube_cluster):
    sched = RTScheduler(rt_kube_cluster.pk, period=0.2, sync_period=0.5)
    stop = threading.Event()
    thread = threading.Thread(target=sched.run, args=(stop,), daemon=True)
    thread.start()
    yield sched
    stop.set()
    thread.join(timeout=15)
    assert not thread.is_alive(), "the scheduler did not stop"


def pod(name, realtime=None, stateless=False, tolerate=True, cpu="100m"):
    labels = {"app": name}
    if realtime:
        labels["rt-scheduling"] = realtime
    if stateless:
        labels["rt.monitoring/stateless"] = "true"
    spec = {
        "schedulerName": "RT-scheduler",
        "containers": [{"name": name, "image": "nginx:1.14.2", "resources": {"requests": {"cpu": cpu}}}],
    }
    if tolerate:
        spec["tolerations"] = [RT_TOLERATION]
    return {"apiVersion": "v1", "kind": "Pod", "metadata": {"name": name, "labels": labels}, "spec": spec}


def realtime_object(name, criticality, period, deadline, wcets):
    return {
        "apiVersion": "rt.scheduling/v1",
        "kind": "RealTime",
        "metadata": {"name": name},
        "spec": {
            "criticality": criticality,
            "rtPeriod": period,
            "rtDeadline": deadline,
            "rtWcets": [{"node": n, "rtWcet": w} for n, w in wcets.items()],
        },
    }


def node_of(kube, ns, name):
    try:
        return kube.read_namespaced_pod(name, ns).spec.node_name
    except client.ApiException:
        return None


def taints_of(kube, node):
    return [(t.key, t.value, t.effect) for t in kube.read_node(node).spec.taints or []]


def test_realtime_objects_pods_binding_eviction_taint_and_rebinding(api, kube, custom, rt_kube_cluster, scheduler):
    cluster, ns = rt_kube_cluster, rt_kube_cluster.namespace
    assert ("RealTime", "RT", "NoSchedule") in taints_of(kube, "node0")
    assert kube.read_node("node2").metadata.labels["rt.scheduling/criticality"] == "C"
    assert ("RealTime", "RT", "NoSchedule") not in taints_of(kube, "node3")

    # RealTime objects made here appear in the Kubernetes API ...
    for body in (
        {"name": "slam", "criticality": "B", "period": 100, "deadline": 100, "wcets": [{"node": "node0", "wcet": 40}]},
        {"name": "lidar", "criticality": "A", "period": 100, "deadline": 100, "stateless": True,
         "wcets": [{"node": "node0", "wcet": 12}, {"node": "node1", "wcet": 12}]},
    ):  # fmt: skip
        response = api.post("/api/v1/realtimes/", {"cluster": cluster.pk, **body}, format="json")
        assert response.status_code == 201, response.data
        assert response.data["sync_state"] == "synced", response.data
    # Written by rt_push jobs, not in the web request (jobs run at once here: no broker).
    assert Job.objects.filter(kind="rt_push", state="succeeded").count() == 2
    obj = custom.get_namespaced_custom_object(*RT[:2], ns, RT[2], "slam")
    assert obj["spec"] == {"criticality": "B", "rtPeriod": 100, "rtDeadline": 100,
                           "rtWcets": [{"node": "node0", "rtWcet": 40}]}  # fmt: skip
    # ... and objects made in the API appear here.
    custom.create_namespaced_custom_object(*RT[:2], ns, RT[2], realtime_object("arm", "C", 8.33, 8, {"node2": 3.8}))
    custom.create_namespaced_custom_object(*RT[:2], ns, RT[2], realtime_object("vision", "A", 50, 50, {"node3": 5}))
    arm = wait_for(lambda: RealTime.objects.filter(cluster=cluster, name="arm").first(), "RealTime arm in the database")
    assert (arm.criticality, arm.period, arm.wcet_pairs()) == ("C", 8.33, [("node2", 3.8)])
    assert arm.to_resource()["spec"] == realtime_object("arm", "C", 8.33, 8, {"node2": 3.8})["spec"]
    wait_for(lambda: RealTime.objects.filter(cluster=cluster, name="vision").exists(), "RealTime vision")

    # Pods linked by label are bound by the RT scheduler.
    kube.create_namespaced_pod(ns, pod("slam", "slam"))
    assert wait_for(lambda: node_of(kube, ns, "slam"), "slam bound") == "node0"
    kube.create_namespaced_pod(ns, pod("lidar", "lidar", stateless=True))
    kube.create_namespaced_pod(ns, pod("arm", "arm"))
    kube.create_namespaced_pod(ns, pod("dashboard", tolerate=False))
    kube.create_namespaced_pod(ns, pod("vision", "vision"))
    # A packs onto the busiest admissible node (node0, next to slam); C only on the C node; the standard pod
    # only where no RealTime taint is, and by LeastAllocated on node3 (4 CPUs) rather than a hollow node (1 CPU,
    # not a node of the cluster's rows, so not real-time).
    assert wait_for(lambda: node_of(kube, ns, "lidar"), "lidar bound") == "node0"
    assert wait_for(lambda: node_of(kube, ns, "arm"), "arm bound") == "node2"
    assert wait_for(lambda: node_of(kube, ns, "dashboard"), "dashboard bound") == "node3"
    lidar_uid = kube.read_namespaced_pod("lidar", ns).metadata.uid

    # vision fits nowhere: it stays pending, with the reason per node on the pod, in an Event, in the database.
    decision = wait_for(
        lambda: RTDecision.objects.filter(cluster=cluster, pod="vision", outcome="pending").first(), "vision decision"
    )
    reasons = {v["node"]: v["reason"] for v in decision.decision["verdicts"]}
    assert reasons["node3"] == "node has no real-time kernel"
    assert reasons["node0"] == "no WCET given for this node"
    assert node_of(kube, ns, "vision") is None
    condition = wait_for(
        lambda: next(
            (c for c in kube.read_namespaced_pod("vision", ns).status.conditions or [] if c.type == "PodScheduled"),
            None,
        ),
        "PodScheduled condition",
    )
    assert condition.status == "False" and "node3: node has no real-time kernel" in condition.message
    # The RT scheduler weighs every node of the API: the cluster's 4 and the session cluster's hollow nodes.
    every = {f"node{i}" for i in range(4)} | SESSION_NODES
    assert {n.metadata.name for n in kube.list_node().items} == every
    message = f"0/{len(every)} nodes are available"
    # The Event follows the condition (the running scheduler sends explanations in the background).
    wait_for(
        lambda: any(
            e.reason == "FailedScheduling" and message in e.message
            for e in kube.list_namespaced_event(ns, field_selector="involvedObject.name=vision").items
        ),
        "vision's FailedScheduling Event",
    )
    bound = RTDecision.objects.get(cluster=cluster, pod="lidar", outcome="bound")
    assert bound.node == "node0" and {v["node"] for v in bound.decision["verdicts"]} == every

    # A robot reports that slam misses deadlines on node0: lidar (A, stateless) is evicted, node0 tainted.
    sent = datetime.now(UTC)
    report = {"node": "node0", "containerName": "slam", "pod": "slam", "missedDeadlinesPeriod": 25,
              "missedDeadlinesTotal": 25, "sentAt": sent.isoformat(),
              "missAt": (sent - timedelta(milliseconds=60)).isoformat()}  # fmt: skip
    response = api.post("/api/v1/rt-reports/", {"cluster": cluster.pk, "reports": [report]}, format="json")
    assert response.status_code == 201, response.data
    [action] = response.data["events"]
    assert action["kind"] == "eviction" and action["victim"] == f"{ns}/lidar", action
    # The eviction called Kubernetes from the rt_reconcile task (in-process here: CONTINUUM_JOBS_EAGER), which
    # claimed the stored report; the request only stored the batch and queued it.
    assert response.data["queued"] == 1 and response.data["stored"] == 1
    [stored] = MonitoringReport.objects.filter(cluster=cluster, violation="period")
    assert stored.reconciled_at is not None and stored.reconciled_at <= RTEvent.objects.get(pk=action["id"]).created
    assert action["eviction_error"] is None
    assert ("rt.monitoring/violation", "true", "NoSchedule") in taints_of(kube, "node0")
    event = RTEvent.objects.get(pk=action["id"])
    assert event.received_at <= event.reconcile_done_at <= event.eviction_sent_at <= event.eviction_done_at
    assert 0 < event.response_ms < 5000
    assert event.response["update_wait"] == pytest.approx(60, abs=1)
    assert set(event.response["measured"]) >= {"reconcile", "trans_kill", "update_wait"}
    # The evicted pod is gone; its replacement is bound elsewhere (node0 is tainted, node1 has lidar's WCET).
    new_uid = wait_for(
        lambda: (p := _pod(kube, ns, "lidar")) is not None and p.metadata.uid != lidar_uid and p.metadata.uid,
        "lidar recreated",
    )
    assert event.recreated == "lidar"
    assert wait_for(lambda: node_of(kube, ns, "lidar"), "lidar re-bound") == "node1"
    assert kube.read_namespaced_pod("lidar", ns).metadata.uid == new_uid
    assert node_of(kube, ns, "slam") == "node0"  # the violator stays

    # The REST report shows up as the container's Monitoring object.
    mon = wait_for(lambda: _custom_object(custom, ns, MON, "slam-slam"), "Monitoring object slam-slam")
    assert mon["spec"]["missedDeadlinesPeriod"] == 25 and mon["spec"]["node"] == "node0"
    # An update of the Monitoring object in the API is a report too: nobody left to evict on node0 -> an alert.
    mon["spec"].update(missedDeadlinesPeriod=30, missedDeadlinesTotal=55)
    custom.replace_namespaced_custom_object(*MON[:2], ns, MON[2], "slam-slam", mon)
    alert = wait_for(lambda: RTEvent.objects.filter(cluster=cluster, kind="alert").first(), "alert from the object")
    assert alert.container == f"{ns}/slam" and "no container may be evicted" in alert.message
    assert wait_for(lambda: Monitoring.objects.get(cluster=cluster, name="slam-slam").missed_total == 55, "counters")
    status = wait_for(lambda: (_custom_object(custom, ns, MON, "slam-slam") or {}).get("status"), "object status")
    assert status["violation"] is True

    # The taint expires (4 s): the scheduler lifts it from the node.
    wait_for(lambda: ("rt.monitoring/violation", "true", "NoSchedule") not in taints_of(kube, "node0"), "taint lifted")
    # The API is written first, the row right after (apps.realtime.monitoring.lift_expired_taints): wait for it.
    taint = wait_for(lambda: NodeTaint.objects.filter(cluster=cluster, lifted_at__isnull=False).first(), "lifted row")
    assert taint.applied_at is not None
    assert ("RealTime", "RT", "NoSchedule") in taints_of(kube, "node0")  # the RT taint stays
    assert scheduler.errors == 0, scheduler.last_error


def _pod(kube, ns, name):
    try:
        return kube.read_namespaced_pod(name, ns)
    except client.ApiException:
        return None


def _custom_object(custom, ns, kind, name):
    try:
        return custom.get_namespaced_custom_object(*kind[:2], ns, kind[2], name)
    except client.ApiException:
        return None


def test_deletions_are_mirrored_both_ways(api, custom, rt_kube_cluster, scheduler):
    cluster, ns = rt_kube_cluster, rt_kube_cluster.namespace
    body = {"cluster": cluster.pk, "name": "cam", "criticality": "A", "period": 10, "deadline": 10,
            "wcets": [{"node": "node1", "wcet": 2}]}  # fmt: skip
    pk = api.post("/api/v1/realtimes/", body, format="json").data["id"]
    assert _custom_object(custom, ns, RT, "cam") is not None
    assert api.delete(f"/api/v1/realtimes/{pk}/").status_code == 204
    assert _custom_object(custom, ns, RT, "cam") is None
    assert Job.objects.filter(kind="rt_delete", state="succeeded").exists()  # deleted by a job
    custom.create_namespaced_custom_object(*RT[:2], ns, RT[2], realtime_object("gps", "B", 10, 10, {"node0": 1}))
    wait_for(lambda: RealTime.objects.filter(cluster=cluster, name="gps").exists(), "gps here")
    # Changed in the API: updated here.
    obj = custom.get_namespaced_custom_object(*RT[:2], ns, RT[2], "gps")
    obj["spec"]["rtDeadline"] = 5
    custom.replace_namespaced_custom_object(*RT[:2], ns, RT[2], "gps", obj)
    wait_for(lambda: RealTime.objects.get(cluster=cluster, name="gps").deadline == 5, "gps deadline updated")
    # Invalid in the API (WCET on a node we do not know): not imported, the reason is on the object's status.
    custom.create_namespaced_custom_object(*RT[:2], ns, RT[2], realtime_object("bad", "A", 10, 10, {"mars": 1}))
    status = wait_for(lambda: (_custom_object(custom, ns, RT, "bad") or {}).get("status"), "status of bad")
    assert "unknown node 'mars'" in status["error"]
    assert not RealTime.objects.filter(name="bad").exists()
    custom.delete_namespaced_custom_object(*RT[:2], ns, RT[2], "gps")
    wait_for(lambda: not RealTime.objects.filter(cluster=cluster, name="gps").exists(), "gps deleted here")


def test_scheduler_survives_an_unreachable_api(kube_admin, api, kube_server, settings):
    from apps.clusters.models import Cluster

    settings.CONTINUUM_KUBE_RETRY_DEADLINE_S = 2  # each cycle's calls are retried until this deadline

    dead = kubeconfig_text(f"https://127.0.0.1:{free_port()}", "token", kube_server.ca_path.read_bytes())
    doc = {"name": "gone", "kubeconfig": dead, "nodes": [{"name": "n1"}]}
    pk = kube_admin.post("/api/v1/clusters/import/", doc, format="json").data["id"]
    sched = RTScheduler(Cluster.objects.get(pk=pk).pk, period=0.01, watch=False)
    began = time.monotonic()
    assert sched.run(max_cycles=3) == 3
    assert sched.errors == 3 and "unreachable" in sched.last_error
    assert time.monotonic() - began < 30


def test_rt_scheduler_command_binds_once_and_refuses_model_only_clusters(kube, rt_kube_cluster, api):
    from django.core.management import CommandError, call_command

    cluster, ns = rt_kube_cluster, rt_kube_cluster.namespace
    body = {"cluster": cluster.pk, "name": "cam", "criticality": "A", "period": 10, "deadline": 10,
            "wcets": [{"node": "node1", "wcet": 2}]}  # fmt: skip
    assert api.post("/api/v1/realtimes/", body, format="json").status_code == 201
    kube.create_namespaced_pod(ns, pod("cam", "cam"))
    out = io.StringIO()
    call_command("rt_scheduler", "--cluster", str(cluster.pk), "--once", stdout=out)
    assert f"bound {ns}/cam -> node1" in out.getvalue()
    assert node_of(kube, ns, "cam") == "node1"
    model_only = api.post("/api/v1/clusters/import/", {"name": "paper", "nodes": [{"name": "x"}]}, format="json")
    with pytest.raises(CommandError, match="model-only cluster"):
        call_command("rt_scheduler", "--cluster", str(model_only.data["id"]), "--once")


def test_decisions_are_stored_after_the_bind_and_a_replayed_event_never_binds_twice(
    api, kube, rt_kube_cluster, scheduler
):
    from apps.realtime.models import RTPod

    cluster, ns = rt_kube_cluster, rt_kube_cluster.namespace
    body = {"cluster": cluster.pk, "name": "cam", "criticality": "A", "period": 10, "deadline": 10,
            "wcets": [{"node": "node1", "wcet": 2}]}  # fmt: skip
    assert api.post("/api/v1/realtimes/", body, format="json").status_code == 201
    kube.create_namespaced_pod(ns, pod("cam", "cam"))
    assert wait_for(lambda: node_of(kube, ns, "cam"), "cam bound") == "node1"
    # The decision ("why" of the dashboard) and the ledger row are written by the scheduler's writer thread.
    decision = wait_for(
        lambda: RTDecision.objects.filter(cluster=cluster, pod="cam", outcome="bound").first(), "cam's decision"
    )
    assert decision.node == "node1" and decision.decision["verdicts"]
    row = wait_for(lambda: RTPod.objects.filter(cluster=cluster, name="cam", node="node1").first(), "ledger row")
    assert row.utilization == pytest.approx(0.2) and row.deleted_at is None

    # The watch replays the pod as it was before its binding (an older resourceVersion): it stays bound.
    stale = kube.api_client.sanitize_for_serialization(kube.read_namespaced_pod("cam", ns))
    stale["spec"].pop("nodeName")
    cycles = scheduler.cycles
    scheduler.pods.apply({"type": "MODIFIED", "raw_object": stale, "object": stale})
    scheduler.wake.set()
    wait_for(lambda: scheduler.cycles >= cycles + 2, "two more cycles")
    assert scheduler.pods.stats()["stale_events"] >= 1

    def scheduled() -> list:
        events = kube.list_namespaced_event(ns, field_selector="involvedObject.name=cam,reason=Scheduled").items
        return [e for e in events if e.source.component == "RT-scheduler"]

    # Events and decisions are written in the background (the writer batches every WRITE_EVERY s): wait for the
    # first Event, then give a second decision or Event the time to appear.
    wait_for(scheduled, "cam's Scheduled Event")
    time.sleep(1.0)
    assert len(scheduled()) == 1
    assert RTDecision.objects.filter(cluster=cluster, pod="cam", outcome="bound").count() == 1
    assert not RTDecision.objects.filter(cluster=cluster, pod="cam").exclude(outcome="bound").exists()
    assert RTPod.objects.get(cluster=cluster, name="cam").node == "node1"
    assert scheduler.errors == 0 and scheduler.ledger.write_errors == 0, scheduler.last_error
