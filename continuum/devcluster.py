"""A local multi-node Kubernetes on loopback: etcd, kube-apiserver, kube-controller-manager, kube-scheduler and
one kubemark hollow node per node of a ``continuum.cluster/v1`` file.

Used by ``scripts/cluster`` (``python -m continuum.devcluster up|status|down``) and by the tests' session
fixture, so both run the same cluster. No Django: it only reads the cluster file and talks HTTP to the API.

A hollow node (``kubemark --morph=kubelet``) is Kubernetes' own simulated node: a real kubelet with a fake
container runtime. It registers a real Node, renews its lease, runs pods' lifecycles (they reach Running
without any container) and, when its process dies, the node lifecycle controller marks it NotReady and taints
it ``node.kubernetes.io/unreachable`` (NoSchedule, then NoExecute, which evicts its pods). What it cannot do
(see ``LIMITS``): its capacity is fixed (1 CPU, 3840 Mi memory, 110 pods) whatever the file says, and nothing
really runs.

A node that says ``"runtime": "real"`` is a real kubelet over its own containerd instead, whose pods are real
processes in the node's own CPU set and memory limit (:mod:`continuum.devcluster_real`); real and hollow nodes mix
in one cluster. etcd only answers clients with a certificate of the cluster's CA (the API server's).

State (pids, ports, credentials, logs, the kubeconfig) lives in one private directory, so ``status`` and
``down`` work from another process than ``up``. What a cluster changes on the host (sysctls, the firewall) is put
back when the machine's last cluster stops (:mod:`continuum.devcluster_host`).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import re
import secrets
import shutil
import signal
import socket
import ssl
import subprocess
import sys
import time
import urllib.error
import urllib.request
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from continuum import devcluster_host as host
from continuum import devcluster_real as real
from continuum.engine.core.cluster import Cluster
from continuum.engine.core.errors import InputError
from continuum.engine.rtkube.rt_model import cluster_from_dict as rt_cluster_from_dict

ROOT = Path(__file__).resolve().parent.parent
BUILD_SCRIPT = ROOT / "scripts" / "build-kube.sh"
DEFAULT_CLUSTER_FILE = ROOT / "clusters" / "local.json"
#: Bounds on a cluster file: each hollow node costs about 90 MB of memory.
MAX_NODES = 200
MAX_FILE_BYTES = 1 << 20
#: Seconds a dead node's pods stay bound (the DefaultTolerationSeconds admission plugin's default is 300).
EVICTION_SECONDS = 10
#: The node lifecycle controller's timing: a node silent for GRACE seconds is NotReady.
NODE_MONITOR_GRACE = "10s"
NODE_MONITOR_PERIOD = "2s"
#: Node labels for the RT attributes (the names apps/realtime/kube.py reads and writes).
CRITICALITY_LABEL = "rt.scheduling/criticality"
THRESHOLD_LABEL = "rt.scheduling/threshold"
#: What a hollow node reports whatever the cluster file says (kubemark's fake cAdvisor and maxPods).
HOLLOW_CAPACITY = {"cpu": "1", "memory": "3840Mi", "pods": "110"}
RUNTIMES = ("hollow", "real")
LIMITS = (
    "hollow nodes report a fixed capacity of 1 CPU, 3840Mi memory and 110 pods (the file's cpu/memory/storage "
    "are not applied); containers do not run (pods reach Running with no process); there is no kube-proxy, "
    "DNS or pod network; links' bandwidth and latency are not emulated"
)

_DNS_LABEL = re.compile(r"^[a-z0-9]([-a-z0-9]{0,61}[a-z0-9])?$")
_NAME = r"[A-Za-z0-9]([-A-Za-z0-9_.]{0,61}[A-Za-z0-9])?"
_QUALIFIED = re.compile(rf"^([a-z0-9]([-a-z0-9]*[a-z0-9])?(\.[a-z0-9]([-a-z0-9]*[a-z0-9])?)*/)?{_NAME}$")
_LABEL_VALUE = re.compile(rf"^({_NAME})?$")


_KUBELET_DIR = re.compile(r"Using (/tmp/hollow-kubelet\.\d+) as root dir for hollow-kubelet")
_KUBELET_DIR_PATH = re.compile(r"^/tmp/hollow-kubelet\.\d+$")


class DevClusterError(RuntimeError):
    """The cluster could not be built, started or reached."""


Progress = Callable[[str], None]


def _stderr(message: str) -> None:
    print(f"[cluster] {message}", file=sys.stderr, flush=True)


# ---- the cluster file --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class HollowNode:
    """A node of the local cluster: hollow (kubemark) unless ``runtime`` is ``"real"``, whose ``cpuset`` (a CPU
    list, else ``cpu`` CPUs carved automatically) and ``memory_mib`` are its own on this machine."""

    name: str
    labels: dict[str, str] = field(default_factory=dict)
    taints: tuple[str, ...] = ()
    runtime: str = "hollow"
    cpuset: str | None = None
    cpu: float | None = None
    memory_mib: float | None = None

    @property
    def real(self) -> bool:
        return self.runtime == "real"

    def to_dict(self) -> dict[str, Any]:
        doc: dict[str, Any] = {"name": self.name, "labels": self.labels, "taints": list(self.taints)}
        if self.real:
            doc.update(runtime=self.runtime, cpuset=self.cpuset, cpu=self.cpu, memory_mib=self.memory_mib)
        return doc

    @classmethod
    def from_dict(cls, doc: Mapping[str, Any]) -> HollowNode:
        return cls(doc["name"], dict(doc["labels"]), tuple(doc["taints"]), doc.get("runtime", "hollow"),
                   doc.get("cpuset"), doc.get("cpu"), doc.get("memory_mib"))  # fmt: skip


#: A node of the local cluster, hollow or real (the older name stays for the hollow-only callers).
NodeSpec = HollowNode


def _check_qualified(key: str, where: str) -> None:
    prefix, _, _ = key.rpartition("/")
    if len(key) > 316 or len(prefix) > 253 or not _QUALIFIED.match(key):
        raise InputError(f"{where}: {key!r} is not a valid Kubernetes label or taint key", "nodes")


def _check_value(value: str, where: str) -> None:
    if not _LABEL_VALUE.match(value):
        raise InputError(f"{where}: {value!r} is not a valid Kubernetes label or taint value", "nodes")


def hollow_nodes(doc: Any) -> list[HollowNode]:
    """The hollow nodes a ``continuum.cluster/v1`` document asks for: its names, ``kubernetes.io/arch`` (and
    the beta label) from ``arch``, its labels, the RT labels and taints (``RealTime=RT:NoSchedule`` on an RT
    node unless the file lists taints). Raises :class:`InputError` naming what Kubernetes would refuse."""
    cluster = Cluster.from_dict(doc)
    if len(cluster.nodes) > MAX_NODES:
        raise InputError(f"a local cluster has at most {MAX_NODES} nodes, the file has {len(cluster.nodes)}", "nodes")
    rt_nodes = {n.name: n for n in rt_cluster_from_dict(doc)}
    out = []
    for node in cluster.nodes.values():
        where = f"node {node.name!r}"
        if not _DNS_LABEL.match(node.name):
            raise InputError(f"{where}: a Kubernetes node name is lower-case letters, digits and '-' (at most 63)",
                             "nodes")  # fmt: skip
        labels = {"kubernetes.io/arch": node.arch, "beta.kubernetes.io/arch": node.arch}
        rt = rt_nodes[node.name]
        if rt.rt:
            labels[THRESHOLD_LABEL] = f"{rt.rt_threshold:g}"
            if rt.criticality:
                labels[CRITICALITY_LABEL] = rt.criticality
        labels.update(node.labels)
        for key, value in labels.items():
            _check_qualified(key, where)
            _check_value(value, where)
        taints = []
        for taint in rt.taints:
            _check_qualified(taint.key, where)
            _check_value(taint.value, where)
            taints.append(str(taint) if taint.value else f"{taint.key}=:{taint.effect}")
        runtime = node.extra.get("runtime", "hollow")
        if runtime not in RUNTIMES:
            raise InputError(f"{where}: runtime must be one of {', '.join(RUNTIMES)}, not {runtime!r}", "nodes")
        cpuset = node.extra.get("cpuset")
        if cpuset is not None:
            if runtime != "real":
                raise InputError(f"{where}: cpuset applies to a node whose runtime is real", "nodes")
            if not isinstance(cpuset, (str, int)) or isinstance(cpuset, bool):
                raise InputError(f'{where}: cpuset must be a CPU list such as "1" or "0-2,5"', "nodes")
            try:
                cpuset = real.format_cpus(real.parse_cpus(str(cpuset)))
            except ValueError as exc:
                raise InputError(f"{where}: cpuset: {exc}", "nodes") from exc
        if runtime == "real" and node.arch != real.host_arch():
            raise InputError(f"{where}: a real node runs on this machine, whose architecture is "
                             f"{real.host_arch()}, not {node.arch}", "nodes")  # fmt: skip
        out.append(HollowNode(node.name, labels, tuple(taints), runtime, cpuset, node.cpu, node.memory_mib))
    return out


def read_cluster_file(path: str | os.PathLike) -> list[HollowNode]:
    """:func:`hollow_nodes` of a file (bounded in size; JSON or YAML)."""
    try:
        with open(path, "rb") as fh:
            raw = fh.read(MAX_FILE_BYTES + 1)
    except OSError as exc:
        raise InputError(f"cannot read {path}: {exc.strerror}", "file") from exc
    if len(raw) > MAX_FILE_BYTES:
        raise InputError(f"{path} is larger than {MAX_FILE_BYTES} bytes", "file")
    try:
        doc = yaml.safe_load(raw)  # JSON is YAML
    except yaml.YAMLError as exc:
        raise InputError(f"{path} is neither JSON nor YAML: {exc}".splitlines()[0], "file") from exc
    return hollow_nodes(doc)


# ---- binaries ----------------------------------------------------------------------------------------------
def build_binaries(timeout: float = 60 * 60, progress: Progress | None = None) -> Path:
    """The directory with kube-apiserver, kube-controller-manager, kube-scheduler and kubemark, building them
    first when the cache is cold (the build's progress goes to our stderr, or to ``progress`` line by line)."""
    proc = subprocess.Popen(["bash", str(BUILD_SCRIPT)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines: list[str] = []
    deadline = time.monotonic() + timeout
    assert proc.stderr is not None and proc.stdout is not None
    for line in proc.stderr:  # the build logs to stderr until it ends
        lines.append(line)
        del lines[:-60]
        if progress is not None:
            progress(line.rstrip())
        else:
            sys.stderr.write(line)
        if time.monotonic() > deadline:
            proc.kill()
            raise DevClusterError(f"{BUILD_SCRIPT.name} did not finish in {timeout:.0f} s")
    out = proc.stdout.read().strip().splitlines()
    if proc.wait() != 0 or not out or not Path(out[-1]).is_dir():
        raise DevClusterError(f"{BUILD_SCRIPT.name} failed (exit {proc.returncode}):\n{''.join(lines)[-3000:]}")
    return Path(out[-1])


# ---- the running cluster -----------------------------------------------------------------------------------
def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def kubeconfig_text(server: str, token: str, ca_pem: bytes, context: str = "continuum-local") -> str:
    import base64

    doc = {
        "apiVersion": "v1",
        "kind": "Config",
        "clusters": [{"name": context, "cluster": {"server": server,
                                                   "certificate-authority-data": base64.b64encode(ca_pem).decode()}}],
        "users": [{"name": f"{context}-admin", "user": {"token": token}}],
        "contexts": [{"name": context, "context": {"cluster": context, "user": f"{context}-admin"}}],
        "current-context": context,
    }  # fmt: skip
    return yaml.safe_dump(doc, sort_keys=False)


def _alive(pid: int, marker: str) -> bool:
    """Whether ``pid`` still runs the process we started (its command line names our state directory or
    binary), so a recycled pid is never signalled."""
    try:
        cmdline = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return marker in cmdline and stat.rsplit(")", 1)[-1].split()[0] != "Z"


def rss_mib(pid: int) -> float | None:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    except OSError:
        return None
    return None


class DevCluster:
    """One local cluster whose state lives in ``state_dir``."""

    def __init__(self, state_dir: str | os.PathLike, etcd: str | None = None) -> None:
        self.dir = Path(state_dir).resolve()
        self.etcd = etcd or shutil.which("etcd") or "/usr/bin/etcd"
        self.state: dict[str, Any] = {}
        #: The processes this object started (the others are known by pid only).
        self._procs: dict[str, subprocess.Popen] = {}
        self._load()

    # -- state --------------------------------------------------------------------------------------------
    @property
    def state_file(self) -> Path:
        return self.dir / "state.json"

    @property
    def kubeconfig_path(self) -> Path:
        return self.dir / "kubeconfig"

    def _load(self) -> None:
        try:
            self.state = json.loads(self.state_file.read_text())
        except (OSError, ValueError):
            self.state = {}

    def _save(self) -> None:
        tmp = self.state_file.with_suffix(".tmp")
        tmp.write_text(json.dumps(self.state, indent=1))
        tmp.replace(self.state_file)

    @property
    def server(self) -> str:
        return f"https://127.0.0.1:{self.state['api_port']}"

    def kubeconfig(self) -> str:
        return self.kubeconfig_path.read_text()

    def processes(self) -> dict[str, int]:
        """Component name -> pid, of what this cluster started (``node/NAME`` for hollow nodes)."""
        return dict(self.state.get("pids", {}))

    def running(self) -> dict[str, bool]:
        return {name: self._alive(name) for name in self.processes()}

    def _alive(self, name: str) -> bool:
        """Whether component ``name`` still runs. Processes started by this object are asked directly (which
        also reaps them); others through /proc, checking that the pid was not recycled."""
        proc = self._procs.get(name)
        if proc is not None:
            return proc.poll() is None
        pid = self.state.get("pids", {}).get(name)
        return pid is not None and _alive(pid, str(self.dir))

    def is_up(self) -> bool:
        alive = self.running()
        return bool(alive) and all(alive.values())

    # -- start ------------------------------------------------------------------------------------------------
    def up(self, nodes: Iterable[HollowNode], bin_dir: Path, *, timeout: float = 600,
           progress: Progress = _stderr) -> Path:  # fmt: skip
        """Start everything and wait until every node is Ready and schedulable; the kubeconfig's path."""
        nodes = list(nodes)
        if any(self.running().values()):
            raise DevClusterError(f"a cluster already runs from {self.dir} (stop it with `down` first)")
        began = time.monotonic()
        deadline = began + timeout
        self._reset()
        for binary in ("kube-apiserver", "kube-controller-manager", "kube-scheduler", "kubemark"):
            if not os.access(bin_dir / binary, os.X_OK):
                raise DevClusterError(f"{bin_dir / binary} is missing (run scripts/build-kube.sh)")
        reals = [n for n in nodes if n.real]
        if reals:
            missing = real.requirements(bin_dir)
            if missing:
                raise DevClusterError(f"real nodes need {'; '.join(missing)}")
        self.state = {"bin_dir": str(bin_dir), "token": secrets.token_hex(24), "pids": {},
                      "nodes": [n.to_dict() for n in nodes], "cluster_id": host.cluster_id(self.dir)}  # fmt: skip
        self._save()
        host.enter(self.dir)
        try:
            images: dict[str, str] = {}
            if reals:
                progress("real nodes: the pause and continuum/base:bookworm images (built once, then cached)")
                images = real.build_images(bin_dir)
                self._plan_real(reals)
            self._credentials()
            self._start_etcd(deadline, progress)
            self._start_apiserver(bin_dir, deadline, progress)
            self.kubeconfig_path.write_text(
                kubeconfig_text(self.server, self.state["token"], (self.dir / "certs" / "apiserver.crt").read_bytes())
            )
            # The nodes first, the controllers once every kubelet reports Ready: a node lifecycle controller that
            # starts while all nodes are NotReady enters "master disruption mode" and (v1.20) was seen never to
            # taint a dead node NoExecute afterwards, so its pods were never evicted.
            for node in nodes:
                if not node.real:
                    self._start_node(bin_dir, node)
            if reals:
                self._start_real_nodes(bin_dir, reals, images, deadline, progress)
            self._save()
            names = [n.name for n in nodes]
            progress(f"{len(nodes) - len(reals)} hollow and {len(reals)} real nodes started, waiting until their "
                     "kubelets report Ready")  # fmt: skip
            self.wait_nodes_ready(names, deadline, progress, untainted=False)
            self._start_controllers(bin_dir, deadline, progress)
            self.wait_nodes_ready(names, deadline, progress)
        except BaseException:
            self.down()
            raise
        self.state["startup_seconds"] = round(time.monotonic() - began, 1)
        self.state["kubelet_dirs"] = self._kubelet_dirs()
        self._save()
        progress(f"cluster up in {self.state['startup_seconds']} s; kubeconfig: {self.kubeconfig_path}")
        return self.kubeconfig_path

    def _ours(self) -> bool:
        """Whether the state directory may be deleted: it is empty or was made by this module."""
        return not self.dir.exists() or self.state_file.exists() or not any(self.dir.iterdir())

    def _kubelet_dirs(self) -> list[str]:
        """The hollow kubelets' root directories, to remove at ``down``: kubemark v1.20 makes them under a
        fixed /tmp (not $TMPDIR) and logs where."""
        found = []
        for name in self.processes():
            if name.startswith("node/"):
                # Every run of the node (a restarted one logs a second directory).
                found += _KUBELET_DIR.findall(self.log_tail(name, 10**7))
        return found

    def _reset(self) -> None:
        if not self._ours():
            raise DevClusterError(f"{self.dir} is not empty and holds no cluster state: choose another directory")
        if self.dir.exists():
            shutil.rmtree(self.dir)
        self.dir.mkdir(parents=True, mode=0o700)
        os.chmod(self.dir, 0o700)

    def _credentials(self) -> None:
        old = os.umask(0o077)
        try:
            (self.dir / "tokens.csv").write_text(
                f"{self.state['token']},continuum-admin,continuum-admin,system:masters\n"
            )
            done = subprocess.run(["openssl", "genrsa", "-out", str(self.dir / "sa.key"), "2048"],
                                  capture_output=True, check=False)  # fmt: skip
            if done.returncode != 0:
                raise DevClusterError(f"openssl genrsa failed: {done.stderr.decode()[-500:]}")
            # The cluster's CA: etcd's serving and peer certificates, and the client certificates of the API server
            # (to etcd, and to real kubelets, which trust only this CA's clients).
            certs = self.dir / "certs"
            certs.mkdir(exist_ok=True)
            ca = certs / "ca"
            _openssl(["req", "-x509", "-new", "-nodes", *_EC_KEY, "-keyout", f"{ca}.key", "-out", f"{ca}.crt",
                      "-days", "3650", "-subj", f"/CN=continuum-local-ca-{secrets.token_hex(4)}"])  # fmt: skip
            issued = (
                # etcd dials its own client port (its gRPC gateway) with its serving certificate.
                ("etcd-server", "etcd", "serverAuth,clientAuth"),
                ("etcd-peer", "etcd-peer", "serverAuth,clientAuth"),
                ("apiserver-etcd-client", "kube-apiserver", "clientAuth"),
                # A real kubelet asks the API server (webhook, under RBAC) whether this client may read logs, exec,
                # ...: the group system:masters answers yes, as kubeadm's certificate of the same name did.
                ("apiserver-kubelet-client", "kube-apiserver-kubelet-client/O=system:masters", "clientAuth"),
            )
            for name, cn, usage in issued:
                _issue(certs, name, cn, usage)
        finally:
            os.umask(old)

    def _spawn(self, name: str, argv: list[str], env: Mapping[str, str] | None = None) -> int:
        logs = self.dir / "logs"
        logs.mkdir(exist_ok=True)
        with open(logs / f"{name.replace('/', '-')}.log", "ab") as log:
            try:
                proc = subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                        start_new_session=True, env={**os.environ, **(env or {})})  # fmt: skip
            except OSError as exc:
                raise DevClusterError(f"cannot run {argv[0]}: {exc}") from exc
        self.state["pids"][name] = proc.pid
        self._procs[name] = proc
        self._save()
        return proc.pid

    def log_tail(self, name: str, chars: int = 2000) -> str:
        path = self.dir / "logs" / f"{name.replace('/', '-')}.log"
        return path.read_text(errors="replace")[-chars:] if path.exists() else ""

    def _wait(self, what: str, check: Callable[[], bool], deadline: float, watch: Iterable[str] = ()) -> None:
        watch = list(watch)
        while time.monotonic() < deadline:
            for name in watch:
                if not self._alive(name):
                    raise DevClusterError(f"{name} exited:\n{self.log_tail(name)}")
            if check():
                return
            time.sleep(0.25)
        tails = "\n".join(f"--- {n}\n{self.log_tail(n)}" for n in watch)
        raise DevClusterError(f"timed out waiting for {what}\n{tails}")

    def _start_etcd(self, deadline: float, progress: Progress) -> None:
        client, peer = free_port(), free_port()
        self.state["etcd_port"] = client
        c = self.dir / "certs"
        # TLS both ways on both ports: a client (or peer) without a certificate of the cluster's CA is refused.
        self._spawn("etcd", [
            self.etcd, f"--data-dir={self.dir / 'etcd'}", "--name=default",
            f"--listen-client-urls=https://127.0.0.1:{client}", f"--advertise-client-urls=https://127.0.0.1:{client}",
            f"--listen-peer-urls=https://127.0.0.1:{peer}", f"--initial-advertise-peer-urls=https://127.0.0.1:{peer}",
            f"--initial-cluster=default=https://127.0.0.1:{peer}",
            f"--cert-file={c / 'etcd-server.crt'}", f"--key-file={c / 'etcd-server.key'}", "--client-cert-auth",
            f"--trusted-ca-file={c / 'ca.crt'}", f"--peer-cert-file={c / 'etcd-peer.crt'}",
            f"--peer-key-file={c / 'etcd-peer.key'}", "--peer-client-cert-auth",
            f"--peer-trusted-ca-file={c / 'ca.crt'}",
        ])  # fmt: skip
        self._wait("etcd", lambda: _port_open(client), deadline, ["etcd"])
        progress(f"etcd listening on 127.0.0.1:{client}")

    def _start_apiserver(self, bin_dir: Path, deadline: float, progress: Progress) -> None:
        self.state["api_port"] = port = free_port()
        d = self.dir
        self._spawn("kube-apiserver", [
            str(bin_dir / "kube-apiserver"), f"--etcd-servers=https://127.0.0.1:{self.state['etcd_port']}",
            f"--etcd-cafile={d / 'certs' / 'ca.crt'}", f"--etcd-certfile={d / 'certs' / 'apiserver-etcd-client.crt'}",
            f"--etcd-keyfile={d / 'certs' / 'apiserver-etcd-client.key'}",
            # Real kubelets authenticate the API server by this certificate (logs, exec) and are reached at their
            # node address (no host name lookups).
            f"--kubelet-client-certificate={d / 'certs' / 'apiserver-kubelet-client.crt'}",
            f"--kubelet-client-key={d / 'certs' / 'apiserver-kubelet-client.key'}",
            "--kubelet-preferred-address-types=InternalIP",
            "--bind-address=127.0.0.1", "--advertise-address=127.0.0.1", f"--secure-port={port}",
            f"--cert-dir={d / 'certs'}", f"--token-auth-file={d / 'tokens.csv'}", "--authorization-mode=Node,RBAC",
            "--service-account-issuer=https://kubernetes.default.svc", f"--service-account-key-file={d / 'sa.key'}",
            f"--service-account-signing-key-file={d / 'sa.key'}", "--disable-admission-plugins=ServiceAccount",
            "--endpoint-reconciler-type=none", "--enable-priority-and-fairness=false",
            "--service-cluster-ip-range=10.96.0.0/16",
            # A pod on a dead node is evicted after this many seconds instead of 5 minutes.
            f"--default-not-ready-toleration-seconds={EVICTION_SECONDS}",
            f"--default-unreachable-toleration-seconds={EVICTION_SECONDS}",
        ])  # fmt: skip
        self._wait("kube-apiserver /readyz", lambda: self._get("/readyz") is not None, deadline, ["kube-apiserver"])
        progress(f"kube-apiserver ready on {self.server}")

    def _start_controllers(self, bin_dir: Path, deadline: float, progress: Progress) -> None:
        kubeconfig = str(self.kubeconfig_path)
        cm_port, sched_port = free_port(), free_port()
        self._spawn("kube-controller-manager", [
            str(bin_dir / "kube-controller-manager"), f"--kubeconfig={kubeconfig}", "--leader-elect=false",
            "--bind-address=127.0.0.1", f"--secure-port={cm_port}", "--port=0",
            f"--node-monitor-grace-period={NODE_MONITOR_GRACE}", f"--node-monitor-period={NODE_MONITOR_PERIOD}",
            # Both need a service account signing setup this cluster does not have (no ServiceAccount plugin).
            "--controllers=*,-serviceaccount-token,-tokencleaner",
        ])  # fmt: skip
        self._spawn("kube-scheduler", [
            str(bin_dir / "kube-scheduler"), f"--kubeconfig={kubeconfig}", "--leader-elect=false",
            "--bind-address=127.0.0.1", f"--secure-port={sched_port}", "--port=0",
        ])  # fmt: skip
        for name, port in (("kube-controller-manager", cm_port), ("kube-scheduler", sched_port)):
            self._wait(f"{name} /healthz", lambda p=port: _healthz(p), deadline, [name])
            progress(f"{name} healthy")

    def _start_node(self, bin_dir: Path, node: HollowNode) -> None:
        # Each hollow node's kubelet root, static-pod dir and fake runtime socket go under its own TMPDIR.
        tmp = self.dir / "nodes" / node.name
        tmp.mkdir(parents=True, exist_ok=True)
        argv = [
            str(bin_dir / "kubemark"), "--morph=kubelet", f"--name={node.name}",
            f"--kubeconfig={self.kubeconfig_path}", f"--kubelet-port={free_port()}", "--kubelet-read-only-port=0",
            f"--node-labels={','.join(f'{k}={v}' for k, v in node.labels.items())}",
        ]  # fmt: skip
        if node.taints:
            argv.append(f"--register-with-taints={','.join(node.taints)}")
        if os.geteuid() == 0 and shutil.which("unshare"):
            # kubemark's hollow kubelet serves /logs/ (the host's /var/log) to anyone who reaches its port
            # (anonymous, every request authorized; no kubemark flag changes it): in a mount namespace of its own, its
            # /var/log is an empty tmpfs (where it also makes its pods' log directories, instead of on the host).
            script = 'mount -t tmpfs -o size=16m,mode=0755 continuum-hollow-log /var/log && exec "$@"'
            argv = ["unshare", "--mount", "--propagation", "private", "--", "sh", "-c", script, "sh", *argv]
        self._spawn(f"node/{node.name}", argv, {"TMPDIR": str(tmp)})

    # -- real nodes -----------------------------------------------------------------------------------------------
    def _plan_real(self, reals: list[HollowNode]) -> None:
        try:
            plans = real.plan(self.state["cluster_id"], [n.to_dict() for n in reals])
        except real.RealNodeError as exc:
            raise DevClusterError(str(exc)) from exc
        self.state["real"] = [p.to_dict() for p in plans]
        self.state["real_ports"] = {p.name: {"kubelet": free_port(), "healthz": free_port()} for p in plans}
        self._save()

    def real_plans(self) -> list[real.RealNodePlan]:
        """Where each real node lives on this machine (CPUs, memory, address, cgroup, bridge)."""
        return [real.RealNodePlan.from_dict(doc) for doc in self.state.get("real", [])]

    def _start_real_nodes(self, bin_dir: Path, reals: list[HollowNode], images: dict[str, str], deadline: float,
                          progress: Progress) -> None:  # fmt: skip
        cid = self.state["cluster_id"]
        plans = self.real_plans()
        try:
            real.add_addresses(cid, plans)
            for p in plans:
                real.make_cgroups(p)
                real.start_containerd(self, p, cid, deadline)
                progress(f"real node {p.name}: CPUs {real.format_cpus(p.cpus)}, {p.memory_mib} MiB, address {p.ip}")
            began = time.monotonic()
            self.import_image(images["pause"], images["base"])
            progress(f"pause and base images imported into {len(plans)} real nodes in {time.monotonic() - began:.1f} s")
            for node in reals:
                self._start_kubelet(bin_dir, node)
        except real.RealNodeError as exc:
            raise DevClusterError(str(exc)) from exc

    def import_image(self, *archives: str | os.PathLike, nodes: Iterable[str] | None = None) -> None:
        """Import image tarballs (docker-archive or OCI, e.g. from ``buildah push IMG docker-archive:FILE:NAME``) into
        the containerd of every real node (or of ``nodes``), the nodes in parallel: a pod that names the image with
        ``imagePullPolicy: Never`` (or a tag other than latest) then runs it there without a pull."""
        from concurrent.futures import ThreadPoolExecutor

        names = [p.name for p in self.real_plans()]
        chosen = names if nodes is None else list(nodes)
        unknown = [n for n in chosen if n not in names]
        if unknown:
            known = ", ".join(names) or "-"
            raise DevClusterError(f"no real node {unknown[0]!r} in this cluster (real nodes: {known})")
        paths = [str(a) for a in archives]
        with ThreadPoolExecutor(max_workers=max(1, len(chosen))) as pool:
            futures = [pool.submit(real.import_images, self, name, paths) for name in chosen]
            try:
                for future in futures:
                    future.result()
            except real.RealNodeError as exc:
                raise DevClusterError(str(exc)) from exc

    def _start_kubelet(self, bin_dir: Path, node: HollowNode) -> None:
        p = next(p for p in self.real_plans() if p.name == node.name)
        self._spawn(f"node/{node.name}", real.kubelet_argv(self, bin_dir, p, node.labels, node.taints))

    def stop_node(self, name: str, sig: int = signal.SIGTERM) -> None:
        """Stop node ``name``'s kubelet (hollow or real; a real node's containerd and pods keep running, as on a
        machine whose kubelet died): the node lifecycle controller then marks it NotReady and evicts its pods."""
        if f"node/{name}" not in self.processes():
            raise DevClusterError(f"no node {name!r} in this cluster")
        self.stop_process(f"node/{name}", sig)

    def restart_node(self, name: str, *, timeout: float = 300, progress: Progress = _stderr) -> None:
        """Start hollow node ``name`` again (after it was stopped, e.g. to fail it) with the same name, labels and
        taints, and wait until it is Ready and the node lifecycle controller lifted its not-ready/unreachable
        taints. Its Node object was kept: the new kubelet takes it over and finishes the deletion of the pods
        evicted meanwhile."""
        spec = next((n for n in self.state.get("nodes", []) if n["name"] == name), None)
        if spec is None:
            raise DevClusterError(f"no node {name!r} in this cluster")
        if self._alive(f"node/{name}"):
            raise DevClusterError(f"node {name!r} still runs")
        node = HollowNode.from_dict(spec)
        if node.real:
            self._start_kubelet(Path(self.state["bin_dir"]), node)
        else:
            self._start_node(Path(self.state["bin_dir"]), node)
        deadline = time.monotonic() + timeout

        def schedulable() -> bool:
            seen = self.nodes().get(name, {})
            stale = {"node.kubernetes.io/not-ready", "node.kubernetes.io/unreachable"}
            return seen.get("ready") == "True" and not stale & set(seen.get("taints", []))

        self._wait(f"node {name} Ready again", schedulable, deadline, [f"node/{name}", "kube-apiserver"])
        self.state["kubelet_dirs"] = self._kubelet_dirs()
        self._save()
        progress(f"{node.runtime} node {name} restarted and Ready")

    # -- the API ----------------------------------------------------------------------------------------------
    def _get(self, path: str, timeout: float = 10) -> Any:
        """GET a path of the API server (JSON decoded; text for non-JSON); ``None`` when it does not answer."""
        ca = self.dir / "certs" / "apiserver.crt"
        if not ca.exists():
            return None
        request = urllib.request.Request(self.server + path, headers={"Authorization": f"Bearer {self.state['token']}"})
        try:
            with urllib.request.urlopen(request, context=ssl.create_default_context(cafile=str(ca)),
                                        timeout=timeout) as response:  # fmt: skip
                body = response.read()
        except (urllib.error.URLError, OSError, ssl.SSLError):
            return None
        try:
            return json.loads(body)
        except ValueError:
            return body.decode(errors="replace")

    def nodes(self) -> dict[str, dict[str, Any]]:
        """Node name -> {"ready": "True"|"False"|"Unknown", "taints": [...], "labels": {...}} from the API."""
        doc = self._get("/api/v1/nodes")
        out = {}
        for item in (doc or {}).get("items", []) if isinstance(doc, dict) else []:
            conditions = {c["type"]: c["status"] for c in item.get("status", {}).get("conditions", [])}
            out[item["metadata"]["name"]] = {
                "ready": conditions.get("Ready", "Unknown"),
                "taints": [t["key"] for t in item.get("spec", {}).get("taints") or []],
                "labels": item["metadata"].get("labels", {}),
                "capacity": item.get("status", {}).get("capacity", {}),
            }
        return out

    def wait_nodes_ready(
        self, names: list[str], deadline: float, progress: Progress = _stderr, *, untainted: bool = True
    ) -> None:
        """Until each node is Ready and (``untainted``) the controller lifted its not-ready taint, so pods can be
        scheduled on it."""
        last = -1

        def ready() -> bool:
            nonlocal last
            seen = self.nodes()
            done = sum(
                1 for n in names
                if seen.get(n, {}).get("ready") == "True"
                and not (untainted and "node.kubernetes.io/not-ready" in seen[n]["taints"])
            )  # fmt: skip
            if done != last:
                progress(f"{done}/{len(names)} nodes Ready{' and schedulable' if untainted else ''}")
                last = done
            return done == len(names)

        self._wait("every node to be Ready", ready, deadline, [f"node/{n}" for n in names] + ["kube-apiserver"])

    # -- status and stop ---------------------------------------------------------------------------------------
    def status(self) -> dict[str, Any]:
        alive = self.running()
        pids = self.processes()
        components = {
            name: {"pid": pids[name], "running": up, "rss_mib": round(rss_mib(pids[name]) or 0, 1) if up else None}
            for name, up in alive.items()
        }
        return {
            "state_dir": str(self.dir),
            "running": bool(alive) and all(alive.values()),
            "server": self.server if "api_port" in self.state else None,
            "kubeconfig": str(self.kubeconfig_path) if self.kubeconfig_path.exists() else None,
            "startup_seconds": self.state.get("startup_seconds"),
            "components": components,
            "nodes": self.nodes() if alive.get("kube-apiserver") else {},
            "real": self.state.get("real", []),
        }

    def stop_process(self, name: str, sig: int = signal.SIGTERM, wait: float = 15) -> None:
        """Signal one component (its process group) and wait for it to end; SIGKILL after ``wait`` s."""
        pid = self.state.get("pids", {}).get(name)
        if pid is None or not self._alive(name):
            return
        try:
            os.killpg(pid, sig)
        except ProcessLookupError:
            return
        end = time.monotonic() + wait
        while time.monotonic() < end and self._alive(name):
            time.sleep(0.1)
        if self._alive(name):
            with contextlib.suppress(ProcessLookupError):
                os.killpg(pid, signal.SIGKILL)
            for _ in range(50):
                if not self._alive(name):
                    break
                time.sleep(0.1)

    def down(self) -> bool:
        """Stop every component (hollow nodes and controllers first, etcd last) and remove the state; whether
        anything was running."""
        pids = self.processes()
        was = any(self.running().values())
        # Real nodes first: their kubelets, then their pods (the kubelet can no longer stop them), containerd and
        # what they made on the host (cgroups, mounts, devices).
        real.teardown(self, self.state.get("cluster_id", host.cluster_id(self.dir)), self.real_plans())
        order = [n for n in pids if n.startswith("node/")] + [
            n for n in ("kube-scheduler", "kube-controller-manager", "kube-apiserver", "etcd") if n in pids
        ]
        for name in order:
            self.stop_process(name)
        for path in set(self.state.get("kubelet_dirs", [])) | set(self._kubelet_dirs()):
            if _KUBELET_DIR_PATH.match(path):
                shutil.rmtree(path, ignore_errors=True)
        host.leave(self.dir)
        if self.dir.exists() and self._ours():
            real.unmount_under([self.dir])
            shutil.rmtree(self.dir, ignore_errors=True)
        self.state = {}
        self._procs = {}
        return was


_EC_KEY = ("-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1")


def _openssl(args: list[str]) -> None:
    done = subprocess.run(["openssl", *args], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise DevClusterError(f"openssl {args[0]} failed: {done.stderr[-500:]}")


def _issue(certs: Path, name: str, cn: str, usage: str) -> None:
    """A key and a certificate of the cluster's CA for ``cn`` (valid for 127.0.0.1 when it serves)."""
    ext = certs / f"{name}.ext"
    ext.write_text("basicConstraints=CA:FALSE\nkeyUsage=critical,digitalSignature,keyEncipherment\n"
                   f"extendedKeyUsage={usage}\nsubjectAltName=IP:127.0.0.1,DNS:localhost\n")  # fmt: skip
    key, csr, crt = (certs / f"{name}.{x}" for x in ("key", "csr", "crt"))
    _openssl(["req", "-new", "-nodes", *_EC_KEY, "-keyout", str(key), "-out", str(csr), "-subj", f"/CN={cn}"])
    _openssl(["x509", "-req", "-in", str(csr), "-CA", str(certs / "ca.crt"), "-CAkey", str(certs / "ca.key"),
              "-CAcreateserial", "-out", str(crt), "-days", "3650", "-extfile", str(ext)])  # fmt: skip
    csr.unlink()
    ext.unlink()


def _port_open(port: int) -> bool:
    with socket.socket() as s:
        s.settimeout(1)
        return s.connect_ex(("127.0.0.1", port)) == 0


def _healthz(port: int) -> bool:
    # The component's self-signed serving certificate: nothing secret is read, only "ok".
    context = ssl._create_unverified_context()
    try:
        with urllib.request.urlopen(f"https://127.0.0.1:{port}/healthz", context=context, timeout=5) as response:
            return response.status == 200
    except (urllib.error.URLError, OSError, ssl.SSLError):
        return False


# ---- command line ------------------------------------------------------------------------------------------
def default_state_dir() -> Path:
    var = os.environ.get("CONTINUUM_VAR_DIR")
    return (Path(var) if var else ROOT / "var") / "kube-cluster"


def _print_status(status: dict[str, Any]) -> None:
    if not status["components"]:
        print(f"no cluster in {status['state_dir']}")
        return
    print(f"cluster in {status['state_dir']}: {'running' if status['running'] else 'NOT fully running'}")
    if status["server"]:
        print(f"  api server: {status['server']}  kubeconfig: {status['kubeconfig']}")
    for name, comp in status["components"].items():
        rss = f"{comp['rss_mib']:.0f} MiB" if comp["rss_mib"] is not None else "-"
        print(f"  {name:32} pid {comp['pid']:>7}  {'up  ' if comp['running'] else 'DOWN'}  rss {rss}")
    for name, node in status["nodes"].items():
        print(f"  node {name:27} Ready={node['ready']:7} taints={','.join(node['taints']) or '-'}")
    for plan in status.get("real", []):
        print(
            f"  real node {plan['name']:22} CPUs {plan['cpus']}  memory {plan['memory_mib']} MiB  address "
            f"{plan['ip']}  cgroup /{plan['cgroup']}"
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="scripts/cluster", description=__doc__.split("\n\n")[0])
    parser.add_argument("--state-dir", type=Path, default=None, help="default: $CONTINUUM_VAR_DIR/kube-cluster")
    sub = parser.add_subparsers(dest="command", required=True)
    up = sub.add_parser("up", help="start the cluster; prints the kubeconfig's path last")
    up.add_argument("cluster_file", nargs="?", default=str(DEFAULT_CLUSTER_FILE))
    up.add_argument("--bin-dir", type=Path, default=None, help="built binaries (default: run scripts/build-kube.sh)")
    up.add_argument("--timeout", type=float, default=600, help="seconds to wait for every node to be Ready")
    st = sub.add_parser("status", help="what runs, with RSS per component, and the nodes' state")
    st.add_argument("--json", action="store_true")
    sub.add_parser("down", help="stop the cluster and remove its state")
    imp = sub.add_parser("import-image", help="import image tarballs into the real nodes' containerd")
    imp.add_argument("archives", nargs="+", type=Path, help="docker-archive or OCI tarballs")
    imp.add_argument("--node", action="append", help="only this real node (repeatable; default: every real node)")
    args = parser.parse_args(argv)
    cluster = DevCluster(args.state_dir or default_state_dir())

    if args.command == "up":
        try:
            nodes = read_cluster_file(args.cluster_file)
        except InputError as exc:
            print(f"scripts/cluster: {exc}", file=sys.stderr)
            return 2
        if cluster.is_up():
            print(f"scripts/cluster: a cluster already runs from {cluster.dir} (`scripts/cluster down` first)",
                  file=sys.stderr)  # fmt: skip
            return 2
        try:
            bin_dir = args.bin_dir or build_binaries()
            path = cluster.up(nodes, bin_dir, timeout=args.timeout)
        except DevClusterError as exc:
            print(f"scripts/cluster: {exc}", file=sys.stderr)
            return 1
        _stderr(f"limits of hollow nodes: {LIMITS}")
        print(path)
        return 0
    if args.command == "import-image":
        missing = [a for a in args.archives if not a.is_file()]
        if missing:
            print(f"scripts/cluster: {missing[0]} is not a file", file=sys.stderr)
            return 2
        if not cluster.is_up():
            print(f"scripts/cluster: no running cluster in {cluster.dir}", file=sys.stderr)
            return 2
        try:
            cluster.import_image(*args.archives, nodes=args.node)
        except DevClusterError as exc:
            print(f"scripts/cluster: {exc}".splitlines()[0], file=sys.stderr)
            return 2
        return 0
    if args.command == "status":
        status = cluster.status()
        if args.json:
            print(json.dumps(status, indent=1))
        else:
            _print_status(status)
        return 0 if status["running"] else 3
    if cluster.down():
        print(f"stopped the cluster in {cluster.dir}")
    else:
        print(f"no cluster ran in {cluster.dir}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
