"""Fixtures for the Kubernetes tests: ONE real multi-node cluster per test session (etcd, kube-apiserver,
kube-controller-manager, kube-scheduler and kubemark hollow nodes: continuum/devcluster.py, as
./scripts/cluster runs it), a fresh namespace per test, and synthetic Node objects per test where a test needs
a node in a given shape (``make_node``; their Leases are renewed so the real node lifecycle controller treats
them as alive). No test runs on a bare kube-apiserver (tests/kubeapi.py's runner is only unit-tested).

If the API server cannot be built or started the fixture FAILS (it never skips): CI must run these tests.
"""

import contextlib
import datetime
import os
import shutil
import threading
import time
import uuid

import pytest
import yaml
from kubernetes import client, config

LEASE_NAMESPACE = "kube-node-lease"
READY = {"type": "Ready", "status": "True", "reason": "KubeletReady", "message": "kubelet is posting ready status"}


class SessionAPIServer:
    """The session cluster's API server as the tests address it (``server``, ``port``, ``token``, ``ca_path``,
    ``kubeconfig()``, ``startup_seconds``): the multi-node cluster's kube-apiserver, not a bare one."""

    def __init__(self, cluster) -> None:
        self.cluster = cluster
        self.server = cluster.server
        self.port = int(cluster.state["api_port"])
        self.token = cluster.state["token"]
        self.ca_path = cluster.dir / "certs" / "apiserver.crt"
        self.startup_seconds = float(cluster.state.get("startup_seconds") or 0)

    def kubeconfig(self) -> str:
        return self.cluster.kubeconfig()


def pytest_collection_modifyitems(session, config, items):
    """test_multinode.py and test_node_failure.py (FIRST) run first in the session. They kill hollow nodes and
    wait for the node lifecycle controller's NoExecute taint; the controller (v1.20) keeps a synthetic node that a
    later test made NotReady and then deleted at the head of its rate-limited NoExecute queue for the rest of the
    session ("no longer present in nodeLister!" every 10 s), so a node killed after that is never tainted
    NoExecute."""
    first = [i for f in FIRST for i in items if i.nodeid.startswith(f"tests/kube/{f}")]
    if first:
        items[:] = first + [i for i in items if i not in first]


#: Files whose tests kill hollow nodes, run first in this order (see pytest_collection_modifyitems).
FIRST = ("test_multinode.py", "test_node_failure.py")


@pytest.fixture(scope="session")
def kube_server(kube_multinode) -> SessionAPIServer:
    """The session's API server: the multi-node cluster's (controller-manager, scheduler and hollow nodes run)."""
    return SessionAPIServer(kube_multinode)


@pytest.fixture(scope="session")
def kubeconfig(kube_server) -> str:
    """A self-contained kubeconfig (inline CA and bearer token in system:masters) of the session cluster."""
    return kube_server.kubeconfig()


@pytest.fixture
def kube(kubeconfig):
    """A CoreV1Api of the test API server, for arranging and inspecting what the gateway did."""
    api_client = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False)
    with api_client:
        yield client.CoreV1Api(api_client)


@pytest.fixture
def kube_namespace(kube):
    """A fresh namespace name per test (a test or the gateway creates it), deleted when the test ends (the
    namespace controller then removes what is in it; never reuse a name: a deleted one is Terminating a while)."""
    name = f"t-{uuid.uuid4().hex[:12]}"
    yield name
    try:
        kube.delete_namespace(name)
    except client.ApiException as exc:
        if exc.status != 404:
            raise


class LeaseKeeper:
    """Renews the kube-node-lease Lease of synthetic nodes from a thread, as their kubelet would.

    The session cluster runs the real node lifecycle controller: a node whose Lease is not renewed within the
    grace period (devcluster.NODE_MONITOR_GRACE, 10 s) is set Ready=Unknown and tainted unreachable, which would
    change a synthetic node under a running test. With its Lease renewed every second the controller leaves the
    Ready condition as the test wrote it (and taints it as it would a real node in that state)."""

    PERIOD = 1.0

    def __init__(self, api_client) -> None:
        self.coordination = client.CoordinationV1Api(api_client)
        self.names: list[str] = []
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, name="lease-keeper", daemon=True)

    @staticmethod
    def _now() -> str:
        return datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%S.%fZ")

    def add(self, node) -> None:
        body = {
            "apiVersion": "coordination.k8s.io/v1",
            "kind": "Lease",
            "metadata": {
                "name": node.metadata.name,
            },  # no owner reference: a node deleted and made again by a test keeps its Lease
            "spec": {"holderIdentity": node.metadata.name, "leaseDurationSeconds": 40, "renewTime": self._now()},
        }
        try:
            self.coordination.create_namespaced_lease(LEASE_NAMESPACE, body)
        except client.ApiException as exc:
            if exc.status != 409:
                raise
        if node.metadata.name not in self.names:
            self.names.append(node.metadata.name)
        if not self.thread.is_alive():
            self.thread.start()

    def _run(self) -> None:
        while not self.stop.wait(self.PERIOD):
            for name in list(self.names):
                # A busy API server or a node a test deleted: renewed at the next tick.
                with contextlib.suppress(Exception):
                    body = {"spec": {"renewTime": self._now()}}
                    self.coordination.patch_namespaced_lease(name, LEASE_NAMESPACE, body)

    def forget(self, name: str) -> None:
        if name in self.names:
            self.names.remove(name)

    def close(self) -> None:
        self.stop.set()
        if self.thread.is_alive():
            self.thread.join(timeout=30)
        for name in self.names:
            try:
                self.coordination.delete_namespaced_lease(name, LEASE_NAMESPACE)
            except client.ApiException as exc:
                if exc.status != 404:
                    raise


@pytest.fixture
def make_node(kube, kube_multinode):
    """Create a synthetic Node object (no kubelet: pods bound to it stay Pending) and play its kubelet:
    ``make_node(name, cpu="4", memory="8Gi", ready="True", taints=[...], ...)``.

    Synthetic, not hollow, because a hollow node's capacity is fixed (1 CPU, 3840Mi) and its kubelet rewrites
    its status: these tests need a given capacity/arch/Ready condition and delete, cordon or fail the nodes they
    use. The real node lifecycle controller runs: :class:`LeaseKeeper` renews each node's Lease so the
    controller treats it as alive and keeps the Ready condition written here (a node made NotReady/Unknown is
    tainted by the controller as a real one would be: tests assert that, see test_gateway's sync test).

    Nodes are cluster-scoped: every node made here (and its Lease) is deleted when the test ends, and names
    must not collide with the session cluster's hollow nodes."""
    made = []
    keeper = LeaseKeeper(kube.api_client)

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
        assert name not in SESSION_NODES, f"{name} is a hollow node of the session cluster"
        body = {
            "apiVersion": "v1",
            "kind": "Node",
            # The labels a kubelet sets on its node (kube-scheduler pins a Deployment's pods by hostname).
            "metadata": {
                "name": name,
                "labels": {"kubernetes.io/arch": arch, "kubernetes.io/hostname": name, **(labels or {})},
            },
            "spec": {"taints": taints or [], "unschedulable": unschedulable},
        }
        created = kube.create_node(body)
        made.append(name)
        keeper.add(created)
        now = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
        capacity = {"cpu": cpu, "memory": memory, "ephemeral-storage": storage, "pods": "110"}
        condition = {**READY, "status": ready, "lastHeartbeatTime": now, "lastTransitionTime": now}
        node = kube.patch_node_status(
            name, {"status": {"capacity": capacity, "allocatable": capacity, "conditions": [condition]}}
        )
        if ready == "True":
            # The TaintNodesByCondition admission plugin tainted the new node not-ready; the node lifecycle
            # controller lifts that taint once it sees Ready, and so does this (the test need not wait for it).
            node = kube.patch_node(name, {"spec": {"taints": taints or None}})
        return node

    make.keeper = keeper
    yield make
    keeper.close()
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
    """The conftest's 4-node edge cluster, imported through the API with the session cluster's kubeconfig,
    a fresh namespace, and the same 4 nodes (Ready) in the Kubernetes API: synthetic Node objects
    (``make_node``), because the tests need their 4-CPU capacity and fail, delete or cordon them (a hollow
    node's capacity is fixed at 1 CPU and it is shared by the whole session)."""
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
# directory. Tests that kill a node use MULTINODE_VICTIM (dead for the rest of the session) or LOST_NODE (restarted
# by its test), so the others stay Ready for every test. HOLLOW_RT_NODES are two RT nodes of criticality A for the
# RT-Kube eviction test (the RT sync writes RT labels and taints onto a cluster's nodes: these are its own).
MULTINODE_VICTIM = "hollow-victim"
LOST_NODE = "hollow-lost"
HOLLOW_RT_NODES = ("hollow-rt-a0", "hollow-rt-a1")
MULTINODE_CLUSTER = {
    "format": "continuum.cluster/v1",
    "nodes": [
        {"name": "hollow-a", "arch": "amd64", "cpu": 4, "memory_mib": 8192, "labels": {"zone": "edge"}},
        {"name": "hollow-b", "arch": "arm64", "cpu": 4, "memory_mib": 8192, "labels": {"zone": "edge"}},
        {"name": "hollow-c", "arch": "amd64", "cpu": 4, "memory_mib": 8192},
        {"name": "hollow-rt", "arch": "arm64", "cpu": 8, "rt": True, "criticality": "C", "rt_threshold": 7.6},
        {"name": MULTINODE_VICTIM, "arch": "amd64", "cpu": 2, "labels": {"zone": "doomed"}},
        {"name": LOST_NODE, "arch": "amd64", "cpu": 4},
        *({"name": n, "arch": "arm64", "cpu": 1, "rt": True, "criticality": "A"} for n in HOLLOW_RT_NODES),
    ],
}

#: The session cluster's hollow nodes: every Kubernetes test sees them in the API beside the nodes it makes.
SESSION_NODES = frozenset(n["name"] for n in MULTINODE_CLUSTER["nodes"])


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
    keep = os.environ.get("CONTINUUM_KEEP_CLUSTER_LOGS")  # a directory: the components' logs are copied there
    if keep:
        shutil.copytree(cluster.dir / "logs", keep, dirs_exist_ok=True)
    cluster.down()


@pytest.fixture
def multinode_api(kube_multinode):
    """A kubernetes ApiClient of the multi-node cluster."""
    api_client = config.new_client_from_config_dict(yaml.safe_load(kube_multinode.kubeconfig()), persist_config=False)
    with api_client:
        yield api_client


@pytest.fixture
def hollow_cluster(api, kube_admin, kube_multinode, kube_namespace):
    """``hollow_cluster(nodes, name=...)``: a Continuum cluster (through the API, with the session cluster's
    kubeconfig and a fresh namespace) whose nodes are hollow nodes of the session cluster, as declared in
    ``nodes`` (``continuum.cluster/v1`` node documents; ``arch`` defaults to the hollow node's). Pods placed
    there reach Running (a real kubelet with a fake runtime), unlike on ``make_node``'s synthetic nodes.

    The declared capacity is the planning input (node sync keeps it, apps.clusters.kube.row_fields): a test
    may declare the boards it models (4 CPUs) while each hollow node reports 1 CPU; what Kubernetes itself
    schedules (requests, kube-scheduler) must fit the 1 CPU, 3840Mi a hollow node has."""
    from apps.clusters.models import Cluster

    archs = {n["name"]: n.get("arch", "amd64") for n in MULTINODE_CLUSTER["nodes"]}

    def make(nodes: list[dict], name: str = "hollow", links: list[dict] | None = None) -> Cluster:
        for node in nodes:
            assert node["name"] in SESSION_NODES, f"{node['name']} is not a hollow node of the session cluster"
        docs = [{"arch": archs[n["name"]], **n} for n in nodes]
        doc = {"name": name, "kubeconfig": kube_multinode.kubeconfig(), "format": "continuum.cluster/v1",
               "nodes": docs, "links": links or []}  # fmt: skip
        response = kube_admin.post("/api/v1/clusters/import/", doc, format="json")
        assert response.status_code == 201, response.data
        pk = response.data["id"]
        response = api.patch(f"/api/v1/clusters/{pk}/", {"namespace": kube_namespace}, format="json")
        assert response.status_code == 200, response.data
        return Cluster.objects.get(pk=pk)

    return make


def wait_for(what: str, check, timeout: float = 180, interval: float = 0.5):
    """Poll ``check()`` until it returns something truthy (returned); fail naming ``what`` after ``timeout`` s
    (generous: the suite runs on a busy 2-core machine; tests wait for conditions, never for fixed times)."""
    deadline = time.monotonic() + timeout
    last = None
    while time.monotonic() < deadline:
        last = check()
        if last:
            return last
        time.sleep(interval)
    pytest.fail(f"timed out after {timeout} s waiting for {what} (last: {last!r})")


def running_on(kube, namespace: str, selector: str = "") -> dict[str, str]:
    """Pod name -> node of the pods of ``namespace`` that are Running (and not being deleted)."""
    pods = kube.list_namespaced_pod(namespace, label_selector=selector).items
    return {
        p.metadata.name: p.spec.node_name
        for p in pods
        if p.status.phase == "Running" and p.metadata.deletion_timestamp is None
    }
