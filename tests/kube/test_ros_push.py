"""ROS graph -> containers -> nodes -> Deployments, end to end through the API into the session's real
multi-node cluster.

The end-to-end test places on three of the session's hollow nodes (``hollow_cluster``): the real Deployment and
ReplicaSet controllers create each Deployment's ReplicaSet and pod, the real kube-scheduler lands the pod on the
node the placement chose (its hostname and architecture node selector), and the hollow kubelet runs it. A hollow
node has 1 CPU whatever a cluster file says, and kube-scheduler checks the requests against it: the containers
are sized to fit (0.4 cores each, so two share a node and a third does not fit: the choice the placement makes
on the thesis' boards at 1.5 of 4 cores, scaled down), and the nodes are declared with their real 1 CPU.
The other tests read and change the Deployment objects on synthetic Node objects (``make_node``: 4 CPUs, their
Leases renewed so the node lifecycle controller treats them as alive; no kubelet), one of which they delete.
"""

import time

import pytest
import yaml
from django.core.files.uploadedfile import SimpleUploadedFile
from kubernetes import client, config

from apps.containers.kube import HASH_ANNOTATION
from apps.containers.models import ContainerDeployment, Placement
from tests.conftest import DATA
from tests.kubeapi import free_port, kubeconfig_text

pytestmark = [pytest.mark.kube, pytest.mark.django_db]


@pytest.fixture
def apps_api(kubeconfig):
    api_client = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False)
    with api_client:
        yield client.AppsV1Api(api_client)


def run(api, url: str, body: dict | None = None) -> dict:
    response = api.post(url, body or {}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] in ("succeeded", "failed"), job
    return job


def deployments(apps_api, namespace: str) -> dict:
    return {d.metadata.name: d for d in apps_api.list_namespaced_deployment(namespace).items}


def wait_for(what: str, check, timeout: float = 120):
    """Poll ``check()`` until it is truthy (returned); fail naming ``what`` after ``timeout`` s (generous: the
    suite runs on a busy 2-core machine)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if value := check():
            return value
        time.sleep(0.25)
    pytest.fail(f"timed out after {timeout} s waiting for {what}")


def running(kube, namespace: str) -> dict:
    """Deployment name -> the node its Running pod is on."""
    out = {}
    for pod in kube.list_namespaced_pod(namespace).items:
        if pod.metadata.deletion_timestamp is None and pod.status.phase == "Running":
            out[pod.metadata.labels["continuum.io/deployment"]] = pod.spec.node_name
    return out


def settled(apps_api, namespace: str) -> dict | None:
    """The Deployments once the controller has observed each one's generation and counted its pod available."""
    found = deployments(apps_api, namespace)
    done = all(
        d.status.observed_generation == d.metadata.generation and d.status.replicas == d.status.available_replicas == 1
        for d in found.values()
    )  # available: the controller's last status write for a pod that runs
    return found if found and done else None


def autoware_placement(api, cluster, cpu: float = 1.5, extra: dict | None = None) -> Placement:
    """Import the Autoware graph, cluster it into 4 containers and place them with super-clustering, all
    through the API. ``cpu`` cores per container: at 1.5 two fit on a 4-core node, so the placement must
    choose which containers share a node."""
    content = (DATA / "autoware_reference_system.json").read_bytes()
    response = api.post(
        "/api/v1/rosgraphs/import/",
        {"file": SimpleUploadedFile("autoware_reference_system.json", content)},
        format="multipart",
    )
    assert response.status_code == 201, response.data
    job = run(api, f"/api/v1/rosgraphs/{response.data['id']}/cluster/", {"containers": 4})
    assert job["state"] == "succeeded", job["error"]
    clustering = api.get(job["result_url"]).data
    assert clustering["container_count"] == 4
    overrides = {c["name"]: {"cpu": cpu, "memory_mib": 256} for c in clustering["containers"]}
    body = {"cluster": cluster.pk, "policy": "superclustering", "overrides": overrides, "overhead_mib": 39}
    job = run(api, f"/api/v1/clusterings/{clustering['id']}/place/", {**body, **(extra or {})})
    assert job["state"] == "succeeded", job["error"]
    return Placement.objects.get(pk=job["result"]["placement"])


#: Hollow nodes of the session cluster and their architecture (the Deployments' node selector names it).
HOLLOW = {"hollow-a": "amd64", "hollow-b": "arm64", "hollow-c": "amd64"}


def test_autoware_clusters_places_and_pushes_end_to_end(api, kube, hollow_cluster, kube_namespace, apps_api):
    cluster = hollow_cluster([{"name": n, "cpu": 1, "memory_mib": 3840} for n in HOLLOW], name="edge")
    placement = autoware_placement(api, cluster, cpu=0.4)
    placed = placement.placed()
    assert len(placed) == 4 and placement.pending_count == 0
    # 0.4 cores each on 1-core nodes: two containers per node at most, so traffic must cross nodes, and
    # super-clustering keeps less of it on the network than the bandwidth-blind baseline.
    assert max(list(placed.values()).count(n) for n in set(placed.values())) == 2
    assert 0 < placement.inter_node_bandwidth < placement.baseline["inter_node_bandwidth"]

    job = run(api, f"/api/v1/placements/{placement.pk}/push/")
    assert job["state"] == "succeeded", job["error"]
    assert job["progress"] == 100
    assert job["result"] == {
        "placement": placement.pk,
        "namespace": kube_namespace,
        "deployments": 4,
        "created": 4,
        "updated": 0,
        "unchanged": 0,
        "failed": 0,
        "page": f"/ros/placements/{placement.pk}/",
    }
    found = deployments(apps_api, kube_namespace)
    assert len(found) == 4
    specs = {c["name"]: c for c in placement.containers["containers"]}
    rows = {d.container: d for d in ContainerDeployment.objects.filter(placement=placement)}
    assert set(rows) == set(placed)
    for container, node in placed.items():
        row = rows[container]
        assert (row.state, row.message, row.node, row.namespace) == ("applied", "created", node, kube_namespace)
        dep = found[row.deployment]
        assert len(row.deployment) <= 63 and dep.spec.replicas == 1 and dep.spec.strategy.type == "Recreate"
        pod = dep.spec.template.spec
        assert pod.host_network is True and pod.dns_policy == "ClusterFirstWithHostNet"
        assert pod.node_selector == {"kubernetes.io/arch": HOLLOW[node], "kubernetes.io/hostname": node}
        assert pod.node_name is None  # pinned through the scheduler, not around it
        (ros,) = pod.containers
        assert ros.resources.requests == {"cpu": "400m", "memory": "256Mi"} and not ros.resources.limits
        env = {e.name: e.value for e in ros.env}
        assert env["CONTINUUM_ROS_NODES"].split() == specs[container]["nodes"]
        assert dep.metadata.annotations["continuum.io/node"] == node
        assert dep.metadata.labels["app.kubernetes.io/managed-by"] == "continuum"
        assert dep.spec.selector.match_labels == {"continuum.io/deployment": row.deployment}

    # The controllers create a ReplicaSet and one pod per Deployment, kube-scheduler binds the pod to the placed
    # node, and that node's kubelet runs it.
    wanted = {rows[c].deployment: n for c, n in placed.items()}
    wait_for(
        "the Deployments' pods Running on the placed nodes",
        lambda: running(kube, kube_namespace) == wanted,
        timeout=180,
    )
    replica_sets = apps_api.list_namespaced_replica_set(kube_namespace).items
    assert sorted(r.metadata.owner_references[0].name for r in replica_sets) == sorted(wanted)
    for pod in kube.list_namespaced_pod(kube_namespace).items:
        assert pod.metadata.owner_references[0].kind == "ReplicaSet"
        assert pod.spec.scheduler_name == "default-scheduler"
    # Once the Deployment controller has written its status, a second push changes nothing: same objects,
    # same resourceVersions, same records.
    found = wait_for("the Deployment controller to observe every Deployment", lambda: settled(apps_api, kube_namespace))
    versions = {name: d.metadata.resource_version for name, d in found.items()}
    again = run(api, f"/api/v1/placements/{placement.pk}/push/")
    assert again["state"] == "succeeded", again["error"]
    assert (again["result"]["created"], again["result"]["updated"], again["result"]["unchanged"]) == (0, 0, 4)
    assert {name: d.metadata.resource_version for name, d in deployments(apps_api, kube_namespace).items()} == versions
    assert {d.container: d.message for d in ContainerDeployment.objects.filter(placement=placement)} == dict.fromkeys(
        placed, "unchanged"
    )


def test_another_placement_of_the_same_clustering_moves_the_same_deployments(
    api, kube_cluster, kube_namespace, apps_api
):
    first = autoware_placement(api, kube_cluster)
    assert run(api, f"/api/v1/placements/{first.pk}/push/")["state"] == "succeeded"
    names = set(deployments(apps_api, kube_namespace))
    # The same containers at 3 cores: one per node now.
    overrides = {c["name"]: {"cpu": 3, "memory_mib": 256} for c in first.clustering.containers}
    job = run(
        api,
        f"/api/v1/clusterings/{first.clustering_id}/place/",
        {"cluster": kube_cluster.pk, "overrides": overrides, "overhead_mib": 39},
    )
    second = Placement.objects.get(pk=job["result"]["placement"])
    assert len(set(second.placed().values())) == 4
    pushed = run(api, f"/api/v1/placements/{second.pk}/push/")
    assert pushed["state"] == "succeeded", pushed["error"]
    assert pushed["result"]["created"] == 0 and pushed["result"]["updated"] == 4
    found = deployments(apps_api, kube_namespace)
    assert set(found) == names  # moved, not duplicated
    old_rows = ContainerDeployment.objects.filter(placement=first)
    assert {(r.state, r.message) for r in old_rows} == {("superseded", f"superseded by placement {second.pk}")}
    for row in ContainerDeployment.objects.filter(placement=second):
        pod = found[row.deployment].spec.template.spec
        assert pod.node_selector["kubernetes.io/hostname"] == second.placed()[row.container]
        assert pod.containers[0].resources.requests["cpu"] == "3"
        assert found[row.deployment].metadata.annotations[HASH_ANNOTATION]


def test_failures_are_recorded_per_container(api, kube, kube_cluster, kube_namespace, apps_api):
    placement = autoware_placement(api, kube_cluster, cpu=3)  # one container per node
    placed = placement.placed()
    gone_container, gone = sorted(placed.items(), key=lambda kv: kv[1])[-1]
    kube.delete_node(gone)
    job = run(api, f"/api/v1/placements/{placement.pk}/push/")
    assert job["state"] == "failed"
    assert f"1 of 4 containers of placement {placement.pk} failed" in job["error"]
    rows = {d.container: d for d in ContainerDeployment.objects.filter(placement=placement)}
    assert rows[gone_container].state == "failed"
    assert rows[gone_container].message == f"node '{gone}' not found in the Kubernetes API"
    assert {c for c, r in rows.items() if r.state == "applied"} == set(placed) - {gone_container}
    found = deployments(apps_api, kube_namespace)
    assert len(found) == 3 and rows[gone_container].deployment not in found


def test_an_unreachable_api_fails_every_container_cleanly(kube_admin, api, kube_server, kube_cluster, settings):
    settings.CONTINUUM_KUBE_RETRY_DEADLINE_S = 2  # refused connections are retried until this deadline
    placement = autoware_placement(api, kube_cluster)
    closed = kubeconfig_text(f"https://127.0.0.1:{free_port()}", "token", kube_server.ca_path.read_bytes())
    response = kube_admin.patch(f"/api/v1/clusters/{kube_cluster.pk}/", {"kubeconfig": closed}, format="json")
    assert response.status_code == 200, response.data
    job = run(api, f"/api/v1/placements/{placement.pk}/push/")
    assert job["state"] == "failed" and "Kubernetes API unreachable" in job["error"]
    rows = ContainerDeployment.objects.filter(placement=placement)
    assert rows.count() == 4 and {r.state for r in rows} == {"failed"}
    assert all("Kubernetes API unreachable" in r.message for r in rows)


def test_pushing_a_placement_again_updates_its_rows_in_place(api, kube_cluster, kube_namespace, apps_api):
    """The rows of a pushed placement are written in one upsert: a second push updates each container's row
    (same row, new state and message) and keeps what the pod watcher stored on it."""
    placement = autoware_placement(api, kube_cluster)
    assert run(api, f"/api/v1/placements/{placement.pk}/push/")["state"] == "succeeded"
    rows = ContainerDeployment.objects.filter(placement=placement)
    before = {r.container: r for r in rows}
    assert len(before) == 4 and {r.message for r in before.values()} == {"created"}
    rows.update(state="failed", message="stale", pod_phase="Running", pod_node="watched-node")
    job = run(api, f"/api/v1/placements/{placement.pk}/push/")
    assert job["state"] == "succeeded", job["error"]
    assert job["result"]["unchanged"] == 4 and job["result"]["created"] == 0
    after = {r.container: r for r in ContainerDeployment.objects.filter(placement=placement)}
    assert {c: r.pk for c, r in after.items()} == {c: r.pk for c, r in before.items()}
    for container, row in after.items():
        assert (row.state, row.message) == ("applied", "unchanged")
        assert (row.pod_phase, row.pod_node) == ("Running", "watched-node")  # the watcher's, untouched
        assert row.deployment == before[container].deployment and row.node == before[container].node
        assert row.updated > before[container].updated
    assert set(deployments(apps_api, kube_namespace)) == {r.deployment for r in after.values()}
