"""RT-Kube's eviction of a Deployment's pod, end to end on the session's real multi-node cluster (issue 12):
Continuum's RT scheduler (a thread) binds the pods on two RT hollow nodes where they reach Running; a robot
reports a deadline miss; Continuum evicts the Deployment's pod (the victim the monitor chose) and taints its
node; the REAL ReplicaSet controller creates a new pod (Continuum does not: the pod has an owner); the RT
scheduler binds that new pod on the OTHER node, where it runs.

The two RT nodes (conftest.HOLLOW_RT_NODES, criticality A, registered with the ``RealTime=RT:NoSchedule`` taint)
serve this test only: the violation taint it causes is removed at the end.
"""

import threading
from datetime import UTC, datetime

import pytest
import yaml
from kubernetes import client, config

from apps.realtime.models import RTEvent, RTPolicy
from apps.realtime.scheduler import RTScheduler
from tests.kube.conftest import HOLLOW_RT_NODES, running_on, wait_for

pytestmark = [pytest.mark.kube, pytest.mark.django_db(transaction=True)]
RT_TOLERATION = {"key": "RealTime", "operator": "Equal", "value": "RT", "effect": "NoSchedule"}
VIOLATION = "rt.monitoring/violation"
FIRST, OTHER = HOLLOW_RT_NODES


@pytest.fixture
def apps_api(kubeconfig):
    api_client = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False)
    with api_client:
        yield client.AppsV1Api(api_client)


@pytest.fixture
def rt_hollow_cluster(api, kube, hollow_cluster):
    # Declared as what they are: 1 CPU RT boards of criticality A (the RT scheduler reads the API's capacity).
    cluster = hollow_cluster(
        [{"name": n, "cpu": 1, "memory_mib": 3840, "rt": True, "criticality": "A"} for n in HOLLOW_RT_NODES],
        name="rt-live",
    )
    RTPolicy.objects.create(cluster=cluster, taint_duration_s=600)  # lasts the test; removed below
    response = api.post("/api/v1/realtimes/sync/", {"cluster": cluster.pk}, format="json")
    assert response.status_code == 202, response.data
    assert api.get(f"/api/v1/jobs/{response.data['id']}/").data["state"] == "succeeded"
    yield cluster
    for name in HOLLOW_RT_NODES:  # the session's next tests see the nodes as they were registered
        node = kube.read_node(name)
        kept = [t for t in node.spec.taints or [] if t.key != VIOLATION]
        if len(kept) != len(node.spec.taints or []):
            kube.patch_node(name, {"spec": {"taints": [t.to_dict() for t in kept] or None}})


@pytest.fixture
def scheduler(rt_hollow_cluster):
    sched = RTScheduler(rt_hollow_cluster.pk, period=0.2, sync_period=1.0)
    stop = threading.Event()
    thread = threading.Thread(target=sched.run, args=(stop,), daemon=True)
    thread.start()
    yield sched
    stop.set()
    thread.join(timeout=60)
    assert not thread.is_alive(), "the scheduler did not stop"


def rt_spec(name: str, stateless: bool = False) -> tuple[dict, dict]:
    """A pod's labels and spec for the RT scheduler (requests sized for a 1-CPU hollow node)."""
    labels = {"app": name, "rt-scheduling": name}
    if stateless:
        labels["rt.monitoring/stateless"] = "true"
    spec = {
        "schedulerName": "RT-scheduler",
        "tolerations": [RT_TOLERATION],
        "containers": [{"name": name, "image": "registry.invalid/ros:1", "resources": {"requests": {"cpu": "100m"}}}],
    }
    return labels, spec


def test_an_evicted_deployment_pod_is_recreated_by_its_controller_and_bound_on_another_node(
    api, kube, apps_api, rt_hollow_cluster, scheduler
):
    cluster, ns = rt_hollow_cluster, rt_hollow_cluster.namespace
    for body in (
        {"name": "slam", "criticality": "B", "period": 100, "deadline": 100, "wcets": [{"node": FIRST, "wcet": 40}]},
        {"name": "lidar", "criticality": "A", "period": 100, "deadline": 100, "stateless": True,
         "wcets": [{"node": FIRST, "wcet": 12}, {"node": OTHER, "wcet": 12}]},
    ):  # fmt: skip
        response = api.post("/api/v1/realtimes/", {"cluster": cluster.pk, **body}, format="json")
        assert response.status_code == 201, response.data
    labels, spec = rt_spec("slam")
    kube.create_namespaced_pod(ns, {"metadata": {"name": "slam", "labels": labels}, "spec": spec})
    labels, spec = rt_spec("lidar", stateless=True)
    apps_api.create_namespaced_deployment(
        ns,
        {
            "metadata": {"name": "lidar"},
            "spec": {
                "replicas": 1,
                "selector": {"matchLabels": {"app": "lidar"}},
                "template": {"metadata": {"labels": labels}, "spec": spec},
            },
        },
    )
    # slam has a WCET on FIRST only; lidar (A) packs onto the busiest admissible node, next to slam.
    running = wait_for("slam and lidar's pod Running", lambda: (r := running_on(kube, ns)) and len(r) == 2 and r)
    assert running["slam"] == FIRST
    [old] = [name for name in running if name.startswith("lidar-")]
    assert running[old] == FIRST
    old_pod = kube.read_namespaced_pod(old, ns)
    owner = old_pod.metadata.owner_references[0]
    assert owner.kind == "ReplicaSet" and owner.controller

    # A robot reports that slam misses deadlines on FIRST: lidar's pod (A, stateless) is the victim.
    sent = datetime.now(UTC).isoformat()
    report = {"node": FIRST, "containerName": "slam", "pod": "slam", "missedDeadlinesPeriod": 25,
              "missedDeadlinesTotal": 25, "sentAt": sent}  # fmt: skip
    response = api.post("/api/v1/rt-reports/", {"cluster": cluster.pk, "reports": [report]}, format="json")
    assert response.status_code == 201, response.data
    [action] = response.data["events"]
    assert action["kind"] == "eviction" and action["victim"] == f"{ns}/{old}", action
    assert action["eviction_error"] is None
    event = RTEvent.objects.get(pk=action["id"])
    assert event.recreated == ""  # it has a controller: Continuum leaves the replacement to it
    assert (VIOLATION, "NoSchedule") in {(t.key, t.effect) for t in kube.read_node(FIRST).spec.taints}

    # The ReplicaSet controller makes a new pod; the RT scheduler binds it on the other node; it runs there.
    new = wait_for(
        "lidar's replacement Running",
        lambda: next((n for n, node in running_on(kube, ns).items() if n.startswith("lidar-") and n != old), None),
    )
    pod = kube.read_namespaced_pod(new, ns)
    assert pod.spec.node_name == OTHER and pod.spec.scheduler_name == "RT-scheduler"
    assert pod.metadata.owner_references[0].uid == owner.uid  # the same ReplicaSet recreated it
    assert old not in {p.metadata.name for p in kube.list_namespaced_pod(ns).items}
    assert running_on(kube, ns)["slam"] == FIRST  # the violator stays
    wait_for(  # the running scheduler sends its Events in the background
        "the RT scheduler's Scheduled Event",
        lambda: any(
            e.source.component == "RT-scheduler" and OTHER in e.message
            for e in kube.list_namespaced_event(ns, field_selector=f"involvedObject.name={new},reason=Scheduled").items
        ),
    )
    assert scheduler.errors == 0, scheduler.last_error
