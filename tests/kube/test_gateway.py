"""The Kubernetes gateway against the session's real multi-node cluster (controllers, scheduler, hollow nodes).

What an operator sees is checked on the session's hollow nodes (``hollow_edge``: real kubelets, pods reach
Running on the node Continuum chose). Tests that delete, fail or cordon a node, or need a given capacity or
Ready condition, place on synthetic Node objects instead (``kube_cluster``/``make_node``: their Leases renewed
so the node lifecycle controller treats them as alive; no kubelet, so pods bound to them stay Pending): the
hollow nodes are shared by the whole session."""

import re
import time

import pytest
from django.conf import settings
from django.test import override_settings

from tests.kube.conftest import SESSION_NODES, running_on
from tests.kube.conftest import wait_for as wait_until
from tests.kubeapi import free_port, kubeconfig_text

pytestmark = [pytest.mark.kube, pytest.mark.django_db]

PARALLEL = ["lidar_driver", "SLAM/Mapper", "path.planner", "Path_Planner", "camera driver", "x" * 80]
#: A fork-join DAG whose task ids are not DNS names (and two of which sanitize alike).
DAG = {
    "format": "continuum.dag/v1",
    "name": "Nav Stack 2",
    "tasks": [
        {"id": "source", "cost": {"cpu": 2}},
        *({"id": t, "cost": {"cpu": 10 + i}} for i, t in enumerate(PARALLEL)),
        {"id": "sink", "cost": {"cpu": 3}},
    ],
    "edges": [
        *({"src": "source", "dst": t, "data": 0.1} for t in PARALLEL),
        *({"src": t, "dst": "sink", "data": 0.1} for t in PARALLEL),
    ],
}
#: Generous: the suite runs on a busy 2-core machine; tests wait for conditions, never for fixed times.
TIMEOUT = 120
DNS_1123_LABEL = re.compile(r"^[a-z0-9]([-a-z0-9]*[a-z0-9])?$")


def run(api, url: str, body: dict | None = None) -> dict:
    """POST an action that starts a job and return the job (jobs run in-process: no broker in tests)."""
    response = api.post(url, body or {}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] in ("succeeded", "failed"), job
    return job


def heft_schedule(api, cluster):
    """Create the application and a HEFT schedule on ``cluster`` through the API; return the Schedule row."""
    from apps.scheduling.models import Schedule

    response = api.post("/api/v1/applications/", {"name": "Nav Stack 2", "dag": DAG}, format="json")
    assert response.status_code == 201, response.data
    job = run(api, f"/api/v1/applications/{response.data['id']}/schedule/", {"cluster": cluster.pk})
    assert job["state"] == "succeeded", job
    return Schedule.objects.get(pk=job["result"]["schedule"])


def wait_for(what: str, check, timeout: float = TIMEOUT):
    """Poll ``check()`` until it is truthy (returned); fail naming ``what`` after ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if value := check():
            return value
        time.sleep(0.25)
    pytest.fail(f"timed out after {timeout} s waiting for {what}")


def taint_set(kube, node: str) -> set:
    return {(t.key, t.value or "", t.effect) for t in kube.read_node(node).spec.taints or []}


def pods_by_name(kube, namespace: str) -> dict:
    return {p.metadata.name: p for p in kube.list_namespaced_pod(namespace).items}


# -- sync ---------------------------------------------------------------------------------------------------


def test_sync_reads_capacity_arch_ready_taints_and_keeps_vanished_nodes(kube_admin, api, kube, kubeconfig, make_node):
    from apps.clusters.models import ComputeNode

    doc = {
        "name": "lab",
        "kubeconfig": kubeconfig,
        "nodes": [
            {"name": "jetson", "arch": "amd64", "cpu": 1, "memory_mib": 1, "speed": 2.5, "processor_class": "gpu"},
            {"name": "retired", "cpu": 2},
        ],
    }
    response = kube_admin.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 201, response.data
    cluster_id = response.data["id"]
    make_node(
        "jetson",
        cpu="6",
        memory="7870Mi",
        storage="58Gi",
        arch="arm64",
        labels={"continuum.io/criticality": "A"},
        taints=[{"key": "rt", "value": "yes", "effect": "NoSchedule"}],
    )
    make_node("rpi-5", cpu="3500m", memory="8253028Ki", storage="0", arch="aarch64", ready="False")
    make_node("vm-1", arch="riscv64", ready="Unknown", unschedulable=True)
    # The real node lifecycle controller taints a node by its Ready condition (NoSchedule, and NoExecute for
    # taint-based eviction): Unknown -> unreachable (replacing the API server's not-ready taint of a new node),
    # False -> not-ready. Wait until it has, so the sync reads settled nodes.
    vm_taints = {
        ("node.kubernetes.io/unreachable", "", "NoSchedule"),
        ("node.kubernetes.io/unreachable", "", "NoExecute"),
        ("node.kubernetes.io/unschedulable", "", "NoSchedule"),
    }
    wait_for(
        "the node lifecycle controller's taints on vm-1 and rpi-5",
        lambda: (
            taint_set(kube, "vm-1") == vm_taints
            and ("node.kubernetes.io/not-ready", "", "NoExecute") in taint_set(kube, "rpi-5")
        ),
    )

    job = run(api, f"/api/v1/clusters/{cluster_id}/sync/")
    assert job["state"] == "succeeded", job
    assert job["progress"] == 100
    # The session cluster's hollow nodes are in the API too: created like the new ones.
    hollow = len(SESSION_NODES)
    assert job["result"] == {
        "cluster": cluster_id,
        "nodes": 3 + hollow,
        "created": 2 + hollow,
        "updated": 1,
        "unchanged": 0,
        "gone": 1,
    }
    nodes = {n.name: n for n in ComputeNode.objects.filter(cluster_id=cluster_id)}
    assert set(nodes) == {"jetson", "rpi-5", "vm-1", "retired"} | SESSION_NODES
    jetson = nodes["jetson"]
    reported = (jetson.reported_cpu, jetson.reported_memory_mib, jetson.reported_storage_mib)
    assert jetson.arch == "arm64" and reported == (6.0, 7870, 58 * 1024)
    # The declared capacity stays the planning input (test_node_capacity.py); nodes sync found plan with the API's.
    assert (jetson.cpu, jetson.memory_mib, jetson.capacity_source) == (1.0, 1, "declared")
    assert jetson.status == "Ready"
    assert jetson.taints == [{"key": "rt", "value": "yes", "effect": "NoSchedule"}]
    assert jetson.labels["continuum.io/criticality"] == "A" and jetson.labels["kubernetes.io/arch"] == "arm64"
    # What Kubernetes does not know about stays as Continuum set it.
    assert (jetson.processor_class, jetson.speed) == ("gpu", 2.5)
    rpi = nodes["rpi-5"]
    assert (rpi.arch, rpi.cpu, rpi.memory_mib, rpi.status) == ("arm64", 3.5, 8253028 // 1024, "NotReady")
    vm = nodes["vm-1"]
    assert vm.status == "Unknown" and vm.arch == "riscv64"
    # unreachable: the node lifecycle controller's taints of an Unknown node; unschedulable: the cordon.
    assert {(t["key"], t["value"], t["effect"]) for t in vm.taints} == vm_taints and len(vm.taints) == 3
    # A hollow node (a real kubelet) reports kubemark's fixed capacity and is Ready.
    hollow_a = nodes["hollow-a"]
    assert (hollow_a.arch, hollow_a.cpu, hollow_a.memory_mib, hollow_a.status) == ("amd64", 1.0, 3840, "Ready")
    assert nodes["retired"].status == "NotReady"  # gone from the API: kept, not deleted

    again = run(api, f"/api/v1/clusters/{cluster_id}/sync/")
    assert again["result"] == {**job["result"], "created": 0, "updated": 0, "unchanged": 3 + hollow, "gone": 0}
    assert api.get(f"/api/v1/clusters/{cluster_id}/").data["last_synced"] is not None


def test_sync_of_an_unreachable_api_fails_the_job_cleanly(kube_admin, api, cluster, kube_server, settings):
    settings.CONTINUUM_KUBE_RETRY_DEADLINE_S = 2  # refused connections are retried until this deadline
    closed = kubeconfig_text(f"https://127.0.0.1:{free_port()}", "token", kube_server.ca_path.read_bytes())
    assert kube_admin.patch(f"/api/v1/clusters/{cluster.pk}/", {"kubeconfig": closed}, format="json").status_code == 200

    job = run(api, f"/api/v1/clusters/{cluster.pk}/sync/")
    assert job["state"] == "failed"
    assert "Kubernetes API unreachable" in job["error"] and "Connection refused" in job["error"]
    assert not cluster.nodes.exclude(status="Ready").exists()  # nothing changed


# -- push ---------------------------------------------------------------------------------------------------
#: Three hollow nodes declared as the 4-CPU boards HEFT plans for (the declared capacity is the planning input;
#: the pushed pods carry no requests, so a hollow node's 1 CPU runs them all).
HOLLOW_EDGE = ("hollow-a", "hollow-b", "hollow-c")


@pytest.fixture
def hollow_edge(hollow_cluster):
    return hollow_cluster([{"name": n, "cpu": 4, "memory_mib": 8192} for n in HOLLOW_EDGE], name="edge")


# One call in flight: the pods are then created strictly in rank order (checked below); with more, they are
# started in that order (tests/kube/test_push_parallel.py).
@override_settings(CONTINUUM_KUBE_PUSH_CONCURRENCY=1)
def test_push_creates_one_bound_pod_per_assignment(api, kube, kube_cluster, kube_namespace):
    schedule = heft_schedule(api, kube_cluster)
    assignments = list(schedule.assignments.all())
    assert len(assignments) == len(DAG["tasks"])
    assert len({a.processor for a in assignments}) > 1  # HEFT spread the fork over several nodes
    # The niceness hook: a niceness on the assignment becomes an annotation.
    first = assignments[0]
    first.niceness = 5
    first.save(update_fields=["niceness"])

    job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert job["state"] == "succeeded", job
    assert job["result"] == {
        "schedule": schedule.pk,
        "namespace": kube_namespace,
        "pods": len(assignments),
        "bound": len(assignments),
        "failed": 0,
    }
    assert kube.read_namespace(kube_namespace).metadata.name == kube_namespace

    pods = pods_by_name(kube, kube_namespace)
    assert len(pods) == len(assignments)
    for a in schedule.assignments.all():
        assert a.placement == "bound", (a.task, a.placement_message)
        assert a.placement_message == f"bound to {a.processor}"
        pod = pods[a.pod_name]
        assert DNS_1123_LABEL.match(a.pod_name) and len(a.pod_name) <= 63
        assert pod.spec.node_name == a.processor
        assert pod.spec.scheduler_name == settings.CONTINUUM_SCHEDULER_NAME
        assert pod.spec.containers[0].image == settings.CONTINUUM_POD_IMAGE
        assert pod.spec.host_network is True and not pod.spec.containers[0].resources.limits
        assert float(pod.metadata.annotations["continuum.io/rank"]) == pytest.approx(schedule.ranks[a.task])
        assert pod.metadata.labels["continuum.io/schedule"] == str(schedule.pk)
        assert pod.metadata.labels["continuum.io/application"] == str(schedule.application_id)
        assert pod.metadata.annotations["continuum.io/task"] == a.task
        assert (pod.metadata.annotations.get("continuum.io/niceness")) == (None if a.pk != first.pk else "5")
    assert len({a.pod_name for a in schedule.assignments.all()}) == len(assignments)
    # Created (and bound, one after the other) in decreasing rank order: the source first, the sink last.
    created = sorted(pods.values(), key=lambda p: int(p.metadata.resource_version))
    assert created[0].metadata.annotations["continuum.io/task"] == "source"
    assert created[-1].metadata.annotations["continuum.io/task"] == "sink"
    # The ids that sanitize alike still get distinct pods.
    planners = [a.pod_name for a in schedule.assignments.filter(task__in=["path.planner", "Path_Planner"])]
    assert len(set(planners)) == 2 and all(n.startswith("nav-stack-2-path-planner-0-") for n in planners)


def test_pushed_pods_run_on_the_chosen_hollow_nodes_and_a_second_push_keeps_them(
    api, kube, hollow_edge, kube_namespace
):
    schedule = heft_schedule(api, hollow_edge)
    assert {a.processor for a in schedule.assignments.all()} == set(HOLLOW_EDGE)  # HEFT spread the fork
    job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert job["state"] == "succeeded", job
    assert job["result"]["bound"] == len(DAG["tasks"])
    # What an operator sees: the chosen node's kubelet admits each pod and runs it, with the Scheduled event
    # the gateway wrote (a hollow kubelet reports none of its own).
    chosen = {a.pod_name: a.processor for a in schedule.assignments.all()}
    wait_until("every pushed pod Running on its node", lambda: running_on(kube, kube_namespace) == chosen)
    events = kube.list_namespaced_event(kube_namespace, field_selector="reason=Scheduled").items
    assert {e.involved_object.name for e in events} == set(chosen)
    uids = {name: p.metadata.uid for name, p in pods_by_name(kube, kube_namespace).items()}

    again = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert again["state"] == "succeeded" and again["result"]["bound"] == len(chosen), again
    assert {name: p.metadata.uid for name, p in pods_by_name(kube, kube_namespace).items()} == uids
    assert running_on(kube, kube_namespace) == chosen


def test_pushing_twice_changes_nothing(api, kube, kube_cluster, kube_namespace):

    schedule = heft_schedule(api, kube_cluster)
    assert run(api, f"/api/v1/schedules/{schedule.pk}/push/")["state"] == "succeeded"
    before = {name: p.metadata.resource_version for name, p in pods_by_name(kube, kube_namespace).items()}
    rows = list(schedule.assignments.values_list("task", "placement", "placement_message", "pod_name"))

    job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert job["state"] == "succeeded", job
    after = {name: p.metadata.resource_version for name, p in pods_by_name(kube, kube_namespace).items()}
    assert after == before
    assert list(schedule.assignments.values_list("task", "placement", "placement_message", "pod_name")) == rows


def test_a_missing_node_fails_its_assignments_and_keeps_the_schedule(
    api, kube, kube_cluster, kube_namespace, make_node
):
    from apps.scheduling.models import Schedule

    schedule = heft_schedule(api, kube_cluster)
    used = sorted({a.processor for a in schedule.assignments.all()})
    gone = used[-1]
    kube.delete_node(gone)

    job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert job["state"] == "failed"
    lost = list(schedule.assignments.filter(processor=gone))
    assert lost
    assert f"{len(lost)} of {len(DAG['tasks'])} placements of schedule {schedule.pk} failed" in job["error"]
    assert f"node '{gone}' not found in the Kubernetes API" in job["error"]
    for a in lost:
        assert a.placement == "failed" and a.placement_message == f"node '{gone}' not found in the Kubernetes API"
    pods = pods_by_name(kube, kube_namespace)
    assert not any(a.pod_name in pods for a in lost)  # no pod left Pending for nobody to bind
    for a in schedule.assignments.exclude(processor=gone):
        assert a.placement == "bound" and pods[a.pod_name].spec.node_name == a.processor
    assert Schedule.objects.filter(pk=schedule.pk).exists()
    assert api.get(f"/api/v1/schedules/{schedule.pk}/").status_code == 200

    # The node comes back: pushing again places what was missing and leaves the rest alone.
    versions = {name: p.metadata.resource_version for name, p in pods.items()}
    make_node(gone)
    assert run(api, f"/api/v1/schedules/{schedule.pk}/push/")["state"] == "succeeded"
    pods = pods_by_name(kube, kube_namespace)
    assert {name: pods[name].metadata.resource_version for name in versions} == versions
    assert all(pods[a.pod_name].spec.node_name == gone for a in schedule.assignments.filter(processor=gone))
    assert set(schedule.assignments.values_list("placement", flat=True)) == {"bound"}


def test_a_pod_bound_elsewhere_is_reported_not_moved(api, kube, kube_cluster, kube_namespace):
    from kubernetes import client

    from apps.scheduling.kube import pod_manifest, pod_name

    schedule = heft_schedule(api, kube_cluster)
    victim = schedule.assignments.first()
    other = next(n.name for n in kube_cluster.nodes.all() if n.name != victim.processor)
    # Someone else created and bound "our" pod to another node before the push.
    name = pod_name(schedule, victim.task, victim.frame)
    kube.create_namespace(client.V1Namespace(metadata=client.V1ObjectMeta(name=kube_namespace)))
    kube.create_namespaced_pod(kube_namespace, pod_manifest(schedule, victim, name))
    binding = client.V1Binding(
        metadata=client.V1ObjectMeta(name=name), target=client.V1ObjectReference(kind="Node", name=other)
    )
    assert kube.create_namespaced_pod_binding(name, kube_namespace, binding, _preload_content=False).status == 201

    job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert job["state"] == "failed"
    victim.refresh_from_db()
    message = f"pod {name} is already bound to node {other!r}, not {victim.processor!r}"
    assert victim.placement == "failed" and victim.placement_message == message
    assert message in job["error"]
    assert kube.read_namespaced_pod(name, kube_namespace).spec.node_name == other
    assert schedule.assignments.filter(placement="bound").count() == len(DAG["tasks"]) - 1


def test_an_unbound_pod_left_by_an_interrupted_push_is_bound(api, kube, kube_cluster, kube_namespace):
    from kubernetes import client

    from apps.scheduling.kube import pod_manifest, pod_name

    schedule = heft_schedule(api, kube_cluster)
    first = schedule.assignments.first()
    name = pod_name(schedule, first.task, first.frame)
    kube.create_namespace(client.V1Namespace(metadata=client.V1ObjectMeta(name=kube_namespace)))
    created = kube.create_namespaced_pod(kube_namespace, pod_manifest(schedule, first, name))

    assert run(api, f"/api/v1/schedules/{schedule.pk}/push/")["state"] == "succeeded"
    pod = kube.read_namespaced_pod(name, kube_namespace)
    assert pod.metadata.uid == created.metadata.uid and pod.spec.node_name == first.processor
    assert len(pods_by_name(kube, kube_namespace)) == len(DAG["tasks"])


def test_kube_sync_command(api, kube_cluster, make_node):
    import json
    from io import StringIO

    from django.core.management import call_command

    make_node("extra", arch="arm64", cpu="2")
    out = StringIO()
    call_command("kube_sync", str(kube_cluster.pk), "--json", stdout=out)
    result = json.loads(out.getvalue())
    # The session cluster's hollow nodes are in the API beside the cluster's 4 nodes and "extra".
    assert result["nodes"] == 5 + len(SESSION_NODES) and result["created"] == 1 + len(SESSION_NODES)
    assert result["gone"] == 0
    assert kube_cluster.nodes.get(name="extra").arch == "arm64"


def test_a_not_ready_node_refuses_its_placements(api, kube, kube_cluster, kube_namespace):
    schedule = heft_schedule(api, kube_cluster)
    node = schedule.assignments.first().processor
    kube.patch_node_status(node, {"status": {"conditions": [{"type": "Ready", "status": "False"}]}})

    job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert job["state"] == "failed" and f"node '{node}' is NotReady" in job["error"]
    assert set(schedule.assignments.filter(processor=node).values_list("placement", flat=True)) == {"failed"}
    assert not schedule.assignments.exclude(processor=node).exclude(placement="bound").exists()


def test_push_to_an_unreachable_api_fails_every_placement_cleanly(kube_admin, api, cluster, kube_server, settings):
    from apps.scheduling.models import Schedule

    settings.CONTINUUM_KUBE_RETRY_DEADLINE_S = 2  # refused connections are retried until this deadline

    server = f"https://127.0.0.1:{free_port()}"
    closed = kubeconfig_text(server, "token", kube_server.ca_path.read_bytes())
    assert kube_admin.patch(f"/api/v1/clusters/{cluster.pk}/", {"kubeconfig": closed}, format="json").status_code == 200
    schedule = heft_schedule(api, cluster)

    job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert job["state"] == "failed"
    assert job["error"].startswith(f"push of schedule {schedule.pk} to cluster 'edge' failed: ")
    assert f"Kubernetes API unreachable at {server}" in job["error"] and "Connection refused" in job["error"]
    for a in schedule.assignments.all():
        assert a.placement == "failed" and "Kubernetes API unreachable" in a.placement_message
    assert Schedule.objects.filter(pk=schedule.pk).exists()
    # The worker carries on: the next job runs normally.
    assert run(api, f"/api/v1/schedules/{schedule.pk}/push/")["state"] == "failed"


def test_a_bad_token_is_reported(kube_admin, api, kube_cluster, kube_server):
    bad = kubeconfig_text(kube_server.server, "not-the-token", kube_server.ca_path.read_bytes())
    response = kube_admin.patch(f"/api/v1/clusters/{kube_cluster.pk}/", {"kubeconfig": bad}, format="json")
    assert response.status_code == 200, response.data
    schedule = heft_schedule(api, kube_cluster)

    job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    assert job["state"] == "failed" and "Kubernetes API answered 401: Unauthorized" in job["error"]
    sync = run(api, f"/api/v1/clusters/{kube_cluster.pk}/sync/")
    assert sync["state"] == "failed" and "401" in sync["error"]
