"""Real nodes in the local cluster (issue 32): a ``continuum.cluster/v1`` file with two ``"runtime": "real"`` nodes
and two hollow ones brings all four Ready in one cluster (continuum/devcluster.py, as ``./scripts/cluster up``
runs it); a pod on a real node is a real process in that node's cgroup and CPU set; a Deployment pushed by
Continuum (the placement push path) runs real replicas; a real kubelet that dies turns its node NotReady and its
pods move; ``down`` leaves the host as it found it. Also the cluster's own surfaces: etcd answers only clients with
a certificate of the cluster's CA, a real kubelet's API refuses anonymous callers, a hollow kubelet's /logs/ no
longer serves the host's /var/log.

Its own cluster, started once for this module (real nodes need root and ``KUBE_BIN_DIR/kubelet``: skipped, with
the reason, only when either is missing; CI runs as root and builds the kubelet). Each stage's time is printed
(``-s``) so the figures in the report are measured ones.
"""

from __future__ import annotations

import http.client
import os
import signal
import ssl
import subprocess
import sys
import time
import urllib.error
import urllib.request
import uuid
from pathlib import Path

import pytest
import yaml
from kubernetes import client, config

from continuum import devcluster_host as host
from continuum import devcluster_real as real
from continuum.devcluster import DevCluster, DevClusterError, build_binaries, hollow_nodes
from continuum.engine.core.errors import InputError
from tests.kube.conftest import wait_for

pytestmark = pytest.mark.kube

REAL = ("real-a", "real-b")
HOLLOW = ("hollow-x", "hollow-y")
CLUSTER = {
    "format": "continuum.cluster/v1",
    "nodes": [
        *({"name": n, "runtime": "real", "cpu": 1, "memory_mib": 1024, "labels": {"zone": "real"}} for n in REAL),
        *({"name": n, "arch": "amd64", "cpu": 1, "labels": {"zone": "hollow"}} for n in HOLLOW),
    ],
}
IMAGE = real.BASE_IMAGE
TIMINGS: dict[str, float] = {}
#: The host as the module found it (sysctls, the root cpuset's balancing, the firewall's KUBE-* lines), and whether
#: another cluster of the machine was running then (its kubelets changed the host already).
BEFORE: dict[str, object] = {}


def host_now() -> dict[str, object]:
    rules = subprocess.run(["iptables-save"], capture_output=True, text=True, check=False).stdout
    return {
        **{name: Path("/proc/sys", name.replace(".", "/")).read_text().strip() for name in host.SYSCTLS},
        "sched_load_balance": (real.CGROUPS / "cpuset" / "cpuset.sched_load_balance").read_text().strip(),
        "kube_rules": sorted(line for line in rules.splitlines() if "KUBE-" in line),
    }


def note(what: str, seconds: float) -> None:
    TIMINGS[what] = round(seconds, 1)
    print(f"[real-nodes] {what}: {seconds:.1f} s (load {os.getloadavg()[0]:.1f})", file=sys.stderr, flush=True)


# -- the cluster file (no cluster needed) ------------------------------------------------------------------------


def test_a_real_node_is_declared_by_its_runtime_with_its_cpu_set():
    nodes = {n.name: n for n in hollow_nodes(CLUSTER)}
    assert nodes["real-a"].real and not nodes["hollow-x"].real
    doc = {"format": "continuum.cluster/v1", "nodes": [{"name": "r", "runtime": "real", "cpuset": "1,0"}]}
    assert hollow_nodes(doc)[0].cpuset == "0,1"


@pytest.mark.parametrize(
    ("node", "problem"),
    [
        ({"name": "r", "runtime": "docker"}, "runtime must be one of hollow, real"),
        ({"name": "r", "runtime": "real", "cpuset": "1-0"}, "not a CPU range"),
        ({"name": "r", "runtime": "real", "cpuset": "one"}, "not a CPU list"),
        ({"name": "r", "runtime": "real", "cpuset": True}, "cpuset must be a CPU list"),
        ({"name": "r", "cpuset": "1"}, "applies to a node whose runtime is real"),
        ({"name": "r", "runtime": "real", "arch": "riscv64"}, "runs on this machine"),
    ],
)
def test_what_a_real_node_cannot_be_is_rejected_by_name(node, problem):
    with pytest.raises(InputError, match=problem):
        hollow_nodes({"format": "continuum.cluster/v1", "nodes": [node]})


@pytest.mark.skipif(not (real.CGROUPS / "cpuset" / "cpuset.cpus").exists(), reason="no cgroup v1 cpuset hierarchy")
def test_cpu_sets_are_carved_apart_and_refused_beyond_the_machine():
    with pytest.raises(real.RealNodeError, match="memory_mib must be between"):
        real.plan("test00", [{"name": "r", "memory_mib": 64}], taken=set())
    # As on an idle machine (this module's cluster may hold every CPU meanwhile): the carving alone.
    free = real.machine_cpus()
    nodes = [{"name": f"r{i}"} for i in range(len(free))]
    plans = real.plan("test00", nodes, taken=set())
    assert sorted(c for p in plans for c in p.cpus) == sorted(free)  # one each, none shared
    assert len({p.ip for p in plans}) == len({p.bridge for p in plans}) == len(plans)
    assert all(p.memory_mib == real.DEFAULT_MEMORY_MIB and p.cgroup == f"continuum-test00-{p.name}" for p in plans)
    with pytest.raises(real.RealNodeError, match="needs 1 CPU"):
        real.plan("test00", [*nodes, {"name": "one-too-many"}], taken=set())
    with pytest.raises(real.RealNodeError, match="not a free CPU"):
        real.plan("test00", [{"name": "r", "cpuset": str(max(free) + 1)}], taken=set())
    if len(free) < 2:
        return
    explicit = real.plan(
        "test00", [{"name": "a", "cpuset": str(free[0])}, {"name": "b", "cpu": 1, "memory_mib": 512}], taken=set()
    )
    assert explicit[0].cpus == (free[0],) and free[0] not in explicit[1].cpus and explicit[1].memory_mib == 512


# -- the running cluster -----------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    if os.geteuid() != 0:
        pytest.skip("real nodes need root (containerd, cgroups, network devices); CI runs as root")
    bin_dir = build_binaries()
    if not os.access(bin_dir / "kubelet", os.X_OK):
        pytest.skip(f"no kubelet in {bin_dir} (scripts/build-kube.sh builds it)")
    # A short state directory: containerd's socket paths are bounded (108 bytes).
    state = Path(f"/tmp/continuum-real-{uuid.uuid4().hex[:8]}")
    devcluster = DevCluster(state)
    BEFORE.update(host_now(), others=bool(list(host.REGISTRY.glob("cluster-*"))))
    began = time.monotonic()
    try:
        devcluster.up(hollow_nodes(CLUSTER), bin_dir, timeout=900, progress=lambda m: print(f"[real-nodes] {m}"))
    except DevClusterError as exc:
        devcluster.down()
        pytest.fail(f"the cluster with real nodes could not be started: {exc}", pytrace=False)
    note("cluster up (2 real + 2 hollow nodes, every node Ready)", time.monotonic() - began)
    yield devcluster
    devcluster.down()
    print(f"[real-nodes] timings: {TIMINGS}", file=sys.stderr)


@pytest.fixture(scope="module")
def api_client(cluster):
    api_client = config.new_client_from_config_dict(yaml.safe_load(cluster.kubeconfig()), persist_config=False)
    with api_client:
        yield api_client


@pytest.fixture(scope="module")
def core(api_client):
    return client.CoreV1Api(api_client)


@pytest.fixture
def namespace(core):
    name = f"r-{uuid.uuid4().hex[:12]}"
    core.create_namespace({"metadata": {"name": name}})
    yield name
    core.delete_namespace(name)


def ready(node) -> str:
    return next((c.status for c in node.status.conditions or [] if c.type == "Ready"), "Unknown")


def running(core, namespace: str, selector: str = "") -> dict[str, str]:
    pods = core.list_namespaced_pod(namespace, label_selector=selector).items
    return {
        p.metadata.name: p.spec.node_name
        for p in pods
        if p.status.phase == "Running" and p.metadata.deletion_timestamp is None
    }


def processes_in(plan: real.RealNodePlan) -> dict[int, str]:
    """pid -> command line of the processes in the real node's cpuset cgroup (its pods)."""
    out = {}
    for procs in (real.CGROUPS / "cpuset" / plan.cgroup).rglob("cgroup.procs"):
        for pid in procs.read_text().split():
            try:
                out[int(pid)] = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode().strip()
            except OSError:
                continue
    return out


def cpus_allowed(pid: int) -> str:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("Cpus_allowed_list:"):
            return line.split()[1]
    return ""


def test_real_and_hollow_nodes_are_ready_in_one_cluster(cluster, core):
    nodes = {n.metadata.name: n for n in core.list_node().items}
    assert set(nodes) == {*REAL, *HOLLOW}
    assert all(ready(n) == "True" for n in nodes.values())
    plans = {p.name: p for p in cluster.real_plans()}
    assert set(plans) == set(REAL)
    # Each real node has its own CPUs (exclusive: their sets do not overlap) and reports them as allocatable.
    assert not set(plans["real-a"].cpus) & set(plans["real-b"].cpus)
    for name in REAL:
        node = nodes[name]
        assert node.status.node_info.container_runtime_version.startswith("containerd://")
        assert node.metadata.labels["zone"] == "real"
        assert int(node.status.allocatable["cpu"]) == len(plans[name].cpus)
        addresses = {a.type: a.address for a in node.status.addresses}
        assert addresses["InternalIP"] == plans[name].ip
        cpuset = real.CGROUPS / "cpuset" / plans[name].cgroup
        assert (cpuset / "cpuset.cpu_exclusive").read_text().strip() == "1"
        assert real.parse_cpus((cpuset / "cpuset.cpus").read_text()) == list(plans[name].cpus)
    assert not nodes["hollow-x"].status.node_info.container_runtime_version.startswith("containerd://")


def test_etcd_answers_only_clients_with_the_clusters_certificate(cluster):
    url = f"https://127.0.0.1:{cluster.state['etcd_port']}/version"
    certs = cluster.dir / "certs"
    anonymous = ssl.create_default_context(cafile=str(certs / "ca.crt"))
    with pytest.raises((ssl.SSLError, urllib.error.URLError, ConnectionError)):
        urllib.request.urlopen(url, context=anonymous, timeout=10).read()
    with pytest.raises((urllib.error.URLError, OSError, http.client.HTTPException)):  # no plain HTTP either
        urllib.request.urlopen(url.replace("https", "http"), timeout=10).read()
    client_ctx = ssl.create_default_context(cafile=str(certs / "ca.crt"))
    client_ctx.load_cert_chain(certs / "apiserver-etcd-client.crt", certs / "apiserver-etcd-client.key")
    assert b"etcdserver" in urllib.request.urlopen(url, context=client_ctx, timeout=10).read()


def _kubelet_port(cluster, name: str) -> int:
    cmdline = Path(f"/proc/{cluster.processes()[f'node/{name}']}/cmdline").read_bytes().split(b"\0")
    flag = next(a for a in cmdline if a.startswith((b"--kubelet-port=", b"--port=")))
    return int(flag.split(b"=")[1])


def _get(url: str) -> tuple[int, bytes]:
    try:
        with urllib.request.urlopen(url, context=ssl._create_unverified_context(), timeout=10) as response:
            return response.status, response.read()
    except urllib.error.HTTPError as exc:
        return exc.code, exc.read()


def test_kubelets_do_not_serve_the_hosts_logs_to_anyone(cluster):
    assert Path("/var/log").is_dir() and any(Path("/var/log").iterdir())
    host_logs = {p.name for p in Path("/var/log").iterdir()}
    # A hollow kubelet (kubemark: plain HTTP, anonymous, no flag for either) sees an empty /var/log of its own.
    status, body = _get(f"http://127.0.0.1:{_kubelet_port(cluster, 'hollow-x')}/logs/")
    assert status == 200 and not [n for n in host_logs if f'href="{n}' in body.decode()]
    # A real kubelet refuses anonymous callers on every path, and has no read-only port.
    plan = cluster.real_plans()[0]
    port = _kubelet_port(cluster, plan.name)
    for path in ("/logs/", "/pods", "/stats/summary", "/exec/x/y/z"):
        assert _get(f"https://{plan.ip}:{port}{path}")[0] == 401, path
    assert subprocess.run(["curl", "-s", "-m", "3", f"http://{plan.ip}:10255/pods"], check=False).returncode != 0


def test_a_pod_on_a_real_node_is_a_real_process_in_its_cpu_set(cluster, core, namespace):
    plan = cluster.real_plans()[1]
    marker = f"{uuid.uuid4().int % 10**6 + 10**6}"  # sleep's argument: finds the process among the machine's
    began = time.monotonic()
    core.create_namespaced_pod(namespace, {
        "metadata": {"name": "real"},
        "spec": {"nodeName": plan.name, "containers": [{
            "name": "c", "image": IMAGE, "imagePullPolicy": "Never", "command": ["sleep", marker],
        }]},
    })  # fmt: skip
    wait_for("the pod Running", lambda: running(core, namespace) == {"real": plan.name})
    note("pod start on a real node (create -> Running)", time.monotonic() - began)
    procs = wait_for("its process in the node's cgroup", lambda: [p for p, c in processes_in(plan).items()
                                                                 if c == f"sleep {marker}"])  # fmt: skip
    assert len(procs) == 1
    assert real.parse_cpus(cpus_allowed(procs[0])) == list(plan.cpus)
    # The pause process of its sandbox is there too, and the kubelet serves its logs through the API server.
    assert any(c == "/pause" for c in processes_in(plan).values())
    assert core.read_namespaced_pod_log("real", namespace) == ""
    core.delete_namespaced_pod("real", namespace, grace_period_seconds=0)
    wait_for("the process gone with the pod", lambda: not [c for c in processes_in(plan).values() if marker in c])


def test_sched_deadline_is_admitted_inside_a_pod_with_only_cap_sys_nice(cluster, core, namespace):
    """The node's exclusive CPU set is a root domain of its own, which the kernel requires of a SCHED_DEADLINE task's
    affinity (a narrower cpuset is refused): a 5 ms / 50 ms reservation inside the container is admitted."""
    plan = cluster.real_plans()[0]
    marker = f"{uuid.uuid4().int % 10**6 + 10**6}"
    chrt = ["chrt", "-d", "--sched-runtime", "5000000", "--sched-deadline", "50000000", "--sched-period", "50000000"]
    core.create_namespaced_pod(namespace, {
        "metadata": {"name": "deadline"},
        "spec": {"nodeName": plan.name, "restartPolicy": "Never", "containers": [{
            "name": "c", "image": IMAGE, "imagePullPolicy": "Never", "command": [*chrt, "0", "sleep", marker],
            "securityContext": {"capabilities": {"add": ["SYS_NICE"]}},
        }]},
    })  # fmt: skip
    wait_for("the pod Running", lambda: running(core, namespace) == {"deadline": plan.name})
    pid = wait_for("its process", lambda: [p for p, c in processes_in(plan).items() if c == f"sleep {marker}"])[0]
    policy = subprocess.run(["chrt", "-p", str(pid)], capture_output=True, text=True, check=True).stdout
    assert "SCHED_DEADLINE" in policy and "5000000/50000000/50000000" in policy


@pytest.mark.django_db
def test_a_deployment_pushed_by_continuum_runs_real_replicas(cluster, core, api, kube_admin, settings):
    from apps.containers.models import ContainerDeployment
    from tests.kube.test_ros_push import autoware_placement, run

    # The operator's pod image: the base image every real node has (never pulled; it idles when given no command).
    settings.CONTINUUM_POD_IMAGE = IMAGE
    namespace = f"p-{uuid.uuid4().hex[:12]}"
    doc = {"name": "real", "kubeconfig": cluster.kubeconfig(), "format": "continuum.cluster/v1", "links": [],
           "nodes": [{"name": n, "arch": "amd64", "cpu": 1, "memory_mib": 1024} for n in REAL]}  # fmt: skip
    response = kube_admin.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 201, response.data
    response = api.patch(f"/api/v1/clusters/{response.data['id']}/", {"namespace": namespace}, format="json")
    assert response.status_code == 200, response.data
    from apps.clusters.models import Cluster

    placement = autoware_placement(api, Cluster.objects.get(pk=response.data["id"]), cpu=0.4)
    placed = placement.placed()
    assert set(placed.values()) == set(REAL)
    began = time.monotonic()
    job = run(api, f"/api/v1/placements/{placement.pk}/push/")
    assert job["state"] == "succeeded", job["error"]
    rows = {d.container: d.deployment for d in ContainerDeployment.objects.filter(placement=placement)}
    want = {rows[c]: node for c, node in placed.items()}

    def replicas() -> dict[str, str]:
        out = {}
        for pod in core.list_namespaced_pod(namespace).items:
            if pod.status.phase == "Running" and pod.metadata.deletion_timestamp is None:
                out[pod.metadata.labels["continuum.io/deployment"]] = pod.spec.node_name
        return out

    wait_for("every pushed Deployment's replica Running on its real node", lambda: replicas() == want)
    note(f"push of {len(want)} Deployments -> every replica Running on real nodes", time.monotonic() - began)
    # Each replica is a real process (the image's `sleep infinity`) in the cgroup of the node it was placed on.
    for plan in cluster.real_plans():
        expected = sum(1 for node in want.values() if node == plan.name)
        idle = [c for c in processes_in(plan).values() if c == "sleep infinity"]
        assert len(idle) == expected, (plan.name, processes_in(plan))
    core.delete_namespace(namespace)


def test_a_killed_real_kubelet_turns_its_node_not_ready_and_its_pods_move(cluster, api_client, core, namespace):
    """Runs after the others: the victim's kubelet is started again at the end."""
    apps = client.AppsV1Api(api_client)
    labels = {"app": "moving"}
    apps.create_namespaced_deployment(namespace, {
        "metadata": {"name": "moving"},
        "spec": {"replicas": 1, "selector": {"matchLabels": labels}, "template": {
            "metadata": {"labels": labels},
            "spec": {"nodeSelector": {"zone": "real"}, "terminationGracePeriodSeconds": 1,
                     "containers": [{"name": "c", "image": IMAGE, "imagePullPolicy": "Never"}]},
        }},
    })  # fmt: skip
    first = wait_for("the replica Running", lambda: running(core, namespace, "app=moving"))
    victim = next(iter(first.values()))
    survivor = next(n for n in REAL if n != victim)
    killed = time.monotonic()
    cluster.stop_node(victim, signal.SIGKILL)
    wait_for(f"{victim} NotReady", lambda: ready(core.read_node(victim)) != "True", timeout=120)
    note("real kubelet killed -> node NotReady", time.monotonic() - killed)
    wait_for(
        f"the replica Running on {survivor}",
        lambda: set(running(core, namespace, "app=moving").values()) == {survivor},
        timeout=240,
    )
    note("real kubelet killed -> its replica Running on the other real node", time.monotonic() - killed)
    began = time.monotonic()
    cluster.restart_node(victim, progress=lambda m: None)
    note("killed real kubelet restarted -> node Ready and schedulable", time.monotonic() - began)


def test_down_leaves_the_host_as_it_found_it(cluster):
    cid = cluster.state["cluster_id"]
    plans = cluster.real_plans()
    others = [p for p in host.REGISTRY.glob("cluster-*") if p.name != f"cluster-{cid}"]
    cluster.down()
    links = subprocess.run(["ip", "-o", "link"], capture_output=True, text=True, check=True).stdout
    assert f"cn{cid}" not in links
    for plan in plans:
        assert not any((h / plan.cgroup).exists() for h in real._hierarchies())
    assert not [m for m in Path("/proc/self/mountinfo").read_text().splitlines() if str(cluster.dir) in m]
    assert not cluster.dir.exists()
    if others or BEFORE["others"]:
        pytest.skip("another cluster runs on this machine: the host's settings come back when the last one stops")
    # The kubelets changed these (overcommit 1, panic 10, panic_on_oops 1, forwarding on, no load balancing
    # across the real nodes' CPU sets, KUBE-* chains): all as before.
    now, before = host_now(), {k: v for k, v in BEFORE.items() if k != "others"}
    if foreign_kubelets():  # kubelets of clusters this code does not manage rewrite their KUBE-* chains meanwhile
        now.pop("kube_rules"), before.pop("kube_rules")
    assert now == before


def foreign_kubelets() -> list[int]:
    """Kubelets (real or hollow) still running on this machine after our cluster stopped: other clusters'."""
    out = []
    for proc in Path("/proc").iterdir():
        try:
            argv0 = (proc / "cmdline").read_bytes().split(b"\0")[0]
        except OSError:
            continue
        if proc.name.isdigit() and argv0.rsplit(b"/", 1)[-1] in (b"kubelet", b"kubemark"):
            out.append(int(proc.name))
    return out


@pytest.mark.skipif(os.geteuid() != 0 or not host._firewall_tools(), reason="changes the firewall: root, iptables")
def test_the_firewall_loses_the_kube_chains_a_cluster_added_and_nothing_else():
    chain, other = f"KUBE-T{uuid.uuid4().hex[:8].upper()}", f"CONTINUUM-T{uuid.uuid4().hex[:8].upper()}"
    baseline = host._save("iptables")
    try:
        for argv in (["-N", chain], ["-A", chain, "-j", "RETURN"], ["-I", "INPUT", "-j", chain], ["-N", other],
                     ["-A", other, "-j", "RETURN"]):  # fmt: skip
            subprocess.run(["iptables", "-w", "-t", "filter", *argv], check=True)
        host._restore_firewall("iptables", baseline)
        after = host._save("iptables")
        assert chain not in after  # the chain and the rule that jumped to it
        assert f":{other}" in after and f"-A {other} -j RETURN" in after  # someone else's stays
    finally:
        for argv in (["-D", "INPUT", "-j", chain], ["-F", chain], ["-X", chain], ["-F", other], ["-X", other]):
            subprocess.run(["iptables", "-w", "-t", "filter", *argv], capture_output=True, check=False)
