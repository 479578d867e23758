"""The local multi-node Kubernetes (continuum/devcluster.py, ./scripts/cluster) is a real one: hollow nodes
register and stay Ready, the real kube-scheduler and controllers run Deployments, pods that Continuum's
gateway binds reach Running on the chosen node, and a node whose process dies turns NotReady on its own."""

import signal
import time
import uuid

import pytest
from kubernetes import client

from continuum.devcluster import HOLLOW_CAPACITY, hollow_nodes
from continuum.engine.core.errors import InputError
from tests.kube.conftest import MULTINODE_CLUSTER, MULTINODE_VICTIM

pytestmark = pytest.mark.kube

#: Generous: the suite runs on a busy 2-core machine. Tests wait for conditions, never for fixed times.
TIMEOUT = 180


def wait_for(what: str, check, timeout: float = TIMEOUT):
    """Poll ``check()`` until it returns something truthy (returned); fail naming ``what`` after ``timeout``."""
    deadline = time.monotonic() + timeout
    last = None
    while time.monotonic() < deadline:
        last = check()
        if last:
            return last
        time.sleep(0.5)
    pytest.fail(f"timed out after {timeout} s waiting for {what} (last: {last!r})")


def ready(node: client.V1Node) -> str:
    return next((c.status for c in node.status.conditions or [] if c.type == "Ready"), "Unknown")


def taint_keys(node: client.V1Node) -> set[str]:
    return {t.key for t in node.spec.taints or []}


@pytest.fixture
def core(multinode_api):
    return client.CoreV1Api(multinode_api)


@pytest.fixture
def namespace(core):
    name = f"m-{uuid.uuid4().hex[:12]}"
    core.create_namespace({"metadata": {"name": name}})
    yield name
    core.delete_namespace(name)


def running_pods(core, namespace: str, selector: str = "") -> list[client.V1Pod]:
    pods = core.list_namespaced_pod(namespace, label_selector=selector).items
    return [p for p in pods if p.status.phase == "Running" and not p.metadata.deletion_timestamp]


# -- the cluster file -> hollow nodes (no cluster needed) -------------------------------------------------------


def test_the_cluster_file_gives_arch_rt_labels_and_taints():
    nodes = {n.name: n for n in hollow_nodes(MULTINODE_CLUSTER)}
    assert nodes["hollow-b"].labels["kubernetes.io/arch"] == "arm64"
    assert nodes["hollow-b"].labels["zone"] == "edge"
    assert nodes["hollow-rt"].taints == ("RealTime=RT:NoSchedule",)
    assert nodes["hollow-rt"].labels["rt.scheduling/criticality"] == "C"
    assert nodes["hollow-rt"].labels["rt.scheduling/threshold"] == "7.6"
    assert nodes["hollow-a"].taints == ()


@pytest.mark.parametrize(
    ("node", "problem"),
    [
        ({"name": "Robot_Board"}, "node name"),
        ({"name": "a", "labels": {"zone": "a,b=c"}}, "label or taint value"),
        ({"name": "a", "labels": {"bad key!": "x"}}, "label or taint key"),
        ({"name": "a", "taints": ["x=y:Sometimes"]}, "unknown effect"),
        ({"name": "a", "arch": "sparc"}, "unknown architecture"),
    ],
)
def test_what_kubernetes_would_refuse_is_rejected_by_name(node, problem):
    with pytest.raises(InputError, match=problem):
        hollow_nodes({"format": "continuum.cluster/v1", "nodes": [node]})


# -- the running cluster ----------------------------------------------------------------------------------------


def test_every_hollow_node_is_ready_with_the_files_labels_and_taints(core):
    nodes = {n.metadata.name: n for n in core.list_node().items}
    assert set(nodes) == {n["name"] for n in MULTINODE_CLUSTER["nodes"]}
    for name, node in nodes.items():
        assert ready(node) == "True", name
        assert "node.kubernetes.io/not-ready" not in taint_keys(node), name
        # The limit of hollow nodes: a fixed capacity whatever the file says.
        assert {k: node.status.capacity[k] for k in HOLLOW_CAPACITY} == HOLLOW_CAPACITY
    assert nodes["hollow-b"].metadata.labels["kubernetes.io/arch"] == "arm64"
    assert nodes["hollow-a"].metadata.labels["kubernetes.io/arch"] == "amd64"
    rt = nodes["hollow-rt"]
    assert [(t.key, t.value, t.effect) for t in rt.spec.taints] == [("RealTime", "RT", "NoSchedule")]
    assert rt.metadata.labels["rt.scheduling/criticality"] == "C"


def test_a_deployment_gets_pods_running_where_the_real_scheduler_puts_them(multinode_api, core, namespace):
    apps = client.AppsV1Api(multinode_api)
    labels = {"app": "web"}
    apps.create_namespaced_deployment(
        namespace,
        {
            "metadata": {"name": "web"},
            "spec": {
                "replicas": 3,
                "selector": {"matchLabels": labels},
                "template": {
                    "metadata": {"labels": labels},
                    "spec": {
                        "nodeSelector": {"zone": "edge"},
                        "containers": [{"name": "web", "image": "registry.invalid/web:1"}],
                    },
                },
            },
        },
    )
    pods = wait_for("3 Running pods", lambda: (p := running_pods(core, namespace, "app=web")) and len(p) == 3 and p)
    # The ReplicaSet controller made them, kube-scheduler placed them on the nodes the selector allows.
    assert all(p.metadata.owner_references[0].kind == "ReplicaSet" for p in pods)
    assert {p.spec.node_name for p in pods} <= {"hollow-a", "hollow-b"}
    assert all(p.spec.scheduler_name == "default-scheduler" for p in pods)
    events = core.list_namespaced_event(namespace, field_selector="reason=Scheduled").items
    assert len({e.involved_object.name for e in events}) >= 3


@pytest.mark.django_db
def test_a_pod_bound_by_the_gateway_runs_on_the_chosen_node(api, kube_admin, kube_multinode, core):
    from apps.scheduling.models import Schedule

    # Continuum's model of the two nodes with the hollow nodes' real capacity (1 CPU), so HEFT splits the fork.
    nodes = [{"name": name, "cpu": 1, "memory_mib": 3840} for name in ("hollow-a", "hollow-b")]
    namespace = f"g-{uuid.uuid4().hex[:12]}"
    doc = {"name": "hollow", "kubeconfig": kube_multinode.kubeconfig(), "format": "continuum.cluster/v1",
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
    assert {a.processor for a in schedule.assignments.all()} == {"hollow-a", "hollow-b"}  # HEFT split the fork

    response = api.post(f"/api/v1/schedules/{schedule.pk}/push/", {}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded", job
    chosen = {a.pod_name: a.processor for a in schedule.assignments.all()}
    # The hollow kubelet of the chosen node admits the pod and runs it (its fake runtime): Running there.
    pods = wait_for(
        "every pushed pod Running",
        lambda: (p := running_pods(core, namespace)) and len(p) == len(chosen) and p,
    )
    assert {p.metadata.name: p.spec.node_name for p in pods} == chosen
    core.delete_namespace(namespace)


def test_a_killed_hollow_node_turns_not_ready_tainted_and_its_pod_is_evicted(kube_multinode, core, namespace):
    """Runs last in this file: the victim node stays dead for the rest of the session (no other test uses it)."""
    core.create_namespaced_pod(
        namespace,
        {
            "metadata": {"name": "doomed"},
            "spec": {"nodeSelector": {"zone": "doomed"}, "containers": [{"name": "c", "image": "registry.invalid/c"}]},
        },
    )
    wait_for("the pod Running on the victim", lambda: running_pods(core, namespace))
    pod = core.read_namespaced_pod("doomed", namespace)
    assert pod.spec.node_name == MULTINODE_VICTIM
    # The DefaultTolerationSeconds admission plugin gave it the short tolerations the cluster is started with.
    tolerations = {t.key: t.toleration_seconds for t in pod.spec.tolerations}
    assert tolerations["node.kubernetes.io/unreachable"] == tolerations["node.kubernetes.io/not-ready"] == 10

    kube_multinode.stop_process(f"node/{MULTINODE_VICTIM}", signal.SIGKILL)
    assert not kube_multinode.running()[f"node/{MULTINODE_VICTIM}"]

    # Nobody writes the node's status: the node lifecycle controller notices the silence on its own.
    node = wait_for(
        "the victim NotReady and tainted unreachable",
        lambda: (
            (n := core.read_node(MULTINODE_VICTIM))
            and ready(n) != "True"
            and "node.kubernetes.io/unreachable" in taint_keys(n)
            and n
        ),
    )
    assert ready(node) == "Unknown"  # the kubelet stopped posting status
    assert all(ready(n) == "True" for n in core.list_node().items if n.metadata.name != MULTINODE_VICTIM)
    # Then the NoExecute taint, and the taint manager evicts the pod once its 10 s toleration runs out (the dead
    # kubelet cannot confirm the deletion, so the pod stays Terminating).
    wait_for(
        "the victim tainted unreachable:NoExecute",
        lambda: any(
            t.key == "node.kubernetes.io/unreachable" and t.effect == "NoExecute"
            for t in core.read_node(MULTINODE_VICTIM).spec.taints or []
        ),
    )
    wait_for(
        "the pod evicted",
        lambda: core.read_namespaced_pod("doomed", namespace).metadata.deletion_timestamp is not None,
    )
