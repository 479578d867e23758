"""Fixtures for the Kubernetes gateway tests: a real kube-apiserver + etcd for the session, a fresh
namespace and a set of Node objects per test.

If the API server cannot be built or started the fixture FAILS (it never skips): CI must run these tests.
"""

import time
import uuid

import pytest
import yaml
from kubernetes import client, config

from tests.kubeapi import KubeAPIError, KubeAPIServer, build_kube_apiserver

READY = {"type": "Ready", "status": "True", "reason": "KubeletReady", "message": "kubelet is posting ready status"}


@pytest.fixture(scope="session")
def kube_server():
    began = time.monotonic()
    try:
        binary = build_kube_apiserver()
        server = KubeAPIServer(binary).start()
    except KubeAPIError as exc:
        pytest.fail(f"the real kube-apiserver is required and could not be started: {exc}", pytrace=False)
    server.total_startup_seconds = time.monotonic() - began
    yield server
    server.stop()


@pytest.fixture(scope="session")
def kubeconfig(kube_server) -> str:
    """A self-contained kubeconfig (inline CA and bearer token in system:masters) for the test API server."""
    return kube_server.kubeconfig()


@pytest.fixture
def kube(kubeconfig):
    """A CoreV1Api of the test API server, for arranging and inspecting what the gateway did."""
    api_client = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False)
    with api_client:
        yield client.CoreV1Api(api_client)


@pytest.fixture
def kube_namespace() -> str:
    """A fresh namespace name per test (deleted namespaces stay Terminating: never reuse one)."""
    return f"t-{uuid.uuid4().hex[:12]}"


@pytest.fixture
def make_node(kube):
    """Create a Node object and play its kubelet and the node lifecycle controller:
    ``make_node(name, cpu="4", memory="8Gi", ready="True", taints=[...], ...)``.

    Nodes are cluster-scoped, so every node made here is deleted when the test ends.
    """
    made = []

    def make(
        name: str,
        *,
        cpu: str = "4",
        memory: str = "8Gi",
        storage: str = "100Gi",
        arch: str = "amd64",
        ready: str = "True",
        labels: dict | None = None,
        taints: list | None = None,
        unschedulable: bool = False,
    ):
        body = {
            "apiVersion": "v1",
            "kind": "Node",
            "metadata": {"name": name, "labels": {"kubernetes.io/arch": arch, **(labels or {})}},
            "spec": {"taints": taints or [], "unschedulable": unschedulable},
        }
        kube.create_node(body)
        made.append(name)
        now = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
        capacity = {"cpu": cpu, "memory": memory, "ephemeral-storage": storage, "pods": "110"}
        condition = {**READY, "status": ready, "lastHeartbeatTime": now, "lastTransitionTime": now}
        node = kube.patch_node_status(
            name, {"status": {"capacity": capacity, "allocatable": capacity, "conditions": [condition]}}
        )
        if ready == "True":
            # The TaintNodesByCondition admission plugin tainted the new node not-ready; the node lifecycle
            # controller (there is none here) lifts that taint once the kubelet reports Ready.
            node = kube.patch_node(name, {"spec": {"taints": taints or None}})
        return node

    yield make
    for name in made:
        try:
            kube.delete_node(name)
        except client.ApiException as exc:
            if exc.status != 404:
                raise


@pytest.fixture
def kube_admin(fleet, django_user_model):
    """An operator of the first fleet, signed in (session), with the permission to set Kubernetes credentials
    (clusters.change_cluster_credentials): fleet tokens may not set a kubeconfig."""
    from django.contrib.auth.models import Permission
    from rest_framework.test import APIClient

    user = django_user_model.objects.create_user("kube-admin")
    fleet.members.add(user)
    user.user_permissions.add(Permission.objects.get(codename="change_cluster_credentials"))
    client = APIClient()
    client.force_login(user)
    return client


@pytest.fixture
def kube_cluster(api, kube_admin, cluster_doc, kubeconfig, kube_namespace, make_node):
    """The conftest's 4-node edge cluster, imported through the API with the test server's kubeconfig,
    a fresh namespace, and the same 4 nodes (Ready) in the Kubernetes API."""
    from apps.clusters.models import Cluster

    response = kube_admin.post(
        "/api/v1/clusters/import/", {"name": "edge", "kubeconfig": kubeconfig, **cluster_doc}, format="json"
    )
    assert response.status_code == 201, response.data
    pk = response.data["id"]
    response = api.patch(f"/api/v1/clusters/{pk}/", {"namespace": kube_namespace}, format="json")
    assert response.status_code == 200, response.data
    for node in cluster_doc["nodes"]:
        make_node(node["name"], cpu=str(node["cpu"]), memory=f"{node['memory_mib']}Mi")
    return Cluster.objects.get(pk=pk)


# ---- a real multi-node cluster (kube-controller-manager, kube-scheduler, kubemark hollow nodes) -------------
# The same implementation as ./scripts/cluster (continuum/devcluster.py), started once per session in a private
# directory. Tests that kill a node use MULTINODE_VICTIM only, so the others stay Ready for every test.
MULTINODE_VICTIM = "hollow-victim"
MULTINODE_CLUSTER = {
    "format": "continuum.cluster/v1",
    "nodes": [
        {"name": "hollow-a", "arch": "amd64", "cpu": 4, "memory_mib": 8192, "labels": {"zone": "edge"}},
        {"name": "hollow-b", "arch": "arm64", "cpu": 4, "memory_mib": 8192, "labels": {"zone": "edge"}},
        {"name": "hollow-rt", "arch": "arm64", "cpu": 8, "rt": True, "criticality": "C", "rt_threshold": 7.6},
        {"name": MULTINODE_VICTIM, "arch": "amd64", "cpu": 2, "labels": {"zone": "doomed"}},
    ],
}


@pytest.fixture(scope="session")
def kube_multinode(tmp_path_factory):
    """A running :class:`continuum.devcluster.DevCluster` shaped by MULTINODE_CLUSTER, every node Ready.

    Builds the binaries on a cold cache (about 20 minutes on 2 cores). Fails, never skips, when it cannot."""
    import atexit
    import sys

    from continuum.devcluster import DevCluster, DevClusterError, build_binaries, hollow_nodes

    def progress(line: str) -> None:
        print(f"[kube_multinode] {line}", file=sys.stderr, flush=True)

    cluster = DevCluster(tmp_path_factory.mktemp("kube-cluster"))
    atexit.register(cluster.down)  # a safety net if the session ends without the tear-down (down() is idempotent)
    try:
        bin_dir = build_binaries(progress=progress)
        cluster.up(hollow_nodes(MULTINODE_CLUSTER), bin_dir, timeout=900, progress=progress)
    except DevClusterError as exc:
        cluster.down()
        pytest.fail(f"the local multi-node Kubernetes is required and could not be started: {exc}", pytrace=False)
    yield cluster
    cluster.down()


@pytest.fixture
def multinode_api(kube_multinode):
    """A kubernetes ApiClient of the multi-node cluster."""
    api_client = config.new_client_from_config_dict(yaml.safe_load(kube_multinode.kubeconfig()), persist_config=False)
    with api_client:
        yield api_client
