"""Real nodes of the local cluster: for a node of a ``continuum.cluster/v1`` file that says ``"runtime": "real"``,
a kubelet v1.20.2 (``KUBE_BIN_DIR/kubelet``) over its own containerd (Debian's ``containerd``, ``runc`` and
``containernetworking-plugins``), whose pods are real processes.

Everything a real node has is its own and named after the cluster (:func:`devcluster_host.cluster_id` of the
state directory), so several clusters coexist on one machine:

- containerd: root, state, socket and CNI configuration under ``STATE/real/NODE``; the CRI's sandbox image is
  ``localhost/pause:3.4.1`` built from ``KUBE_BIN_DIR/pause`` and the base image ``continuum/base:bookworm``
  (``scripts/build-images.sh``), both imported with ``ctr -n k8s.io images import``, never pulled;
- the node address ``10.250.S.N/32`` on a bridge device ``cn<id>`` (the kubelet refuses loopback; S is a free
  slot of the machine, N the node's index), its pods in ``10.(128+S).N.0/24`` on the CNI bridge ``cn<id>p<N>``;
- the cgroup ``/continuum-<id>-<node>`` in every hierarchy (the kubelet's ``--cgroup-root``): an exclusive CPU
  set (cgroup v1 ``cpuset.cpu_exclusive`` with the root cpuset's ``sched_load_balance`` off, so each node's CPUs
  are a root domain of their own and SCHED_DEADLINE is admitted inside; the whole machine's tasks are then not
  load-balanced across those sets until the last cluster stops) and a memory limit. The node's allocatable CPU
  and memory are its share (``--kube-reserved`` takes the rest of the machine the kubelet reports as capacity);
- the kubelet's API on the node address: TLS, no anonymous access, client certificates of the cluster's CA (the
  API server's) or tokens the API server accepts; the read-only port is off, healthz on loopback.

The kubelet and containerd processes themselves run outside the node's cgroup (only the pods are in it).
"""

from __future__ import annotations

import contextlib
import ipaddress
import math
import os
import platform
import re
import shutil
import signal
import subprocess
import time
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

ROOT = Path(__file__).resolve().parent.parent
IMAGES_SCRIPT = ROOT / "scripts" / "build-images.sh"
PAUSE_IMAGE = "localhost/pause:3.4.1"
BASE_IMAGE = "continuum/base:bookworm"
#: Debian packages a real node needs (scripts/cluster installs them).
PACKAGES = ("containerd", "runc", "containernetworking-plugins")
CGROUPS = Path("/sys/fs/cgroup")
CNI_BIN = Path("/usr/lib/cni")
DEFAULT_MEMORY_MIB = 2048
#: Below this a kubelet's pods (and the eviction threshold) do not fit.
MIN_MEMORY_MIB = 128
#: Unix socket paths are limited to 108 bytes (containerd adds ".ttrpc").
MAX_SOCKET = 100
_CPU_LIST = re.compile(r"^\d+(-\d+)?(,\d+(-\d+)?)*$")


class RealNodeError(RuntimeError):
    """A real node could not be prepared or started."""


class Cluster(Protocol):
    """What this module needs of :class:`continuum.devcluster.DevCluster`."""

    dir: Path
    state: dict[str, Any]

    def _spawn(self, name: str, argv: list[str], env: dict[str, str] | None = None) -> int: ...

    def _alive(self, name: str) -> bool: ...

    def stop_process(self, name: str, sig: int = signal.SIGTERM, wait: float = 15) -> None: ...

    def _wait(self, what: str, check: Any, deadline: float, watch: Iterable[str] = ()) -> None: ...


def host_arch() -> str:
    machine = platform.machine().lower()
    return {"x86_64": "amd64", "aarch64": "arm64", "armv7l": "arm", "riscv64": "riscv64"}.get(machine, machine)


def parse_cpus(text: str) -> list[int]:
    """``"0-2,5"`` -> ``[0, 1, 2, 5]``; :class:`ValueError` for anything else."""
    text = text.strip()
    if not _CPU_LIST.match(text):
        raise ValueError(f"{text!r} is not a CPU list such as '1' or '0-2,5'")
    out: set[int] = set()
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        if int(hi or lo) < int(lo) or int(hi or lo) > 4095:
            raise ValueError(f"{part!r} is not a CPU range")
        out.update(range(int(lo), int(hi or lo) + 1))
    return sorted(out)


def format_cpus(cpus: Iterable[int]) -> str:
    return ",".join(str(c) for c in sorted(cpus))


def machine_cpus() -> list[int]:
    return parse_cpus((CGROUPS / "cpuset" / "cpuset.effective_cpus").read_text())


def _exclusive_taken(own: str) -> set[int]:
    """CPUs held by exclusive cpusets of others (other clusters, an experiment) at the top of the hierarchy."""
    taken: set[int] = set()
    for d in (CGROUPS / "cpuset").iterdir():
        if d.is_dir() and not d.name.startswith(own):
            with contextlib.suppress(OSError, ValueError):
                if (d / "cpuset.cpu_exclusive").read_text().strip() == "1":
                    taken.update(parse_cpus((d / "cpuset.cpus").read_text()))
    return taken


@dataclass(frozen=True)
class RealNodePlan:
    """Where a real node lives on this machine."""

    name: str
    index: int
    cpus: tuple[int, ...]
    memory_mib: int
    ip: str
    pod_subnet: str
    bridge: str
    cgroup: str

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "index": self.index, "cpus": format_cpus(self.cpus),
                "memory_mib": self.memory_mib, "ip": self.ip, "pod_subnet": self.pod_subnet,
                "bridge": self.bridge, "cgroup": self.cgroup}  # fmt: skip

    @classmethod
    def from_dict(cls, doc: dict[str, Any]) -> RealNodePlan:
        return cls(doc["name"], doc["index"], tuple(parse_cpus(doc["cpus"])), doc["memory_mib"], doc["ip"],
                   doc["pod_subnet"], doc["bridge"], doc["cgroup"])  # fmt: skip


def requirements(bin_dir: Path) -> list[str]:
    """What this machine lacks for real nodes (empty when it can run them)."""
    missing = []
    if os.geteuid() != 0:
        missing.append("root (containerd, cgroups, network devices)")
    if not os.access(bin_dir / "kubelet", os.X_OK) or not os.access(bin_dir / "pause", os.X_OK):
        missing.append(f"{bin_dir}/kubelet and pause (scripts/build-kube.sh)")
    if not (CGROUPS / "cpuset" / "cpuset.cpus").exists():
        missing.append("the cgroup v1 cpuset hierarchy at /sys/fs/cgroup/cpuset")
    for tool in ("containerd", "ctr", "runc", "ip"):
        if shutil.which(tool) is None and not Path("/usr/sbin", tool).exists():
            missing.append(f"{tool} (Debian: {' '.join(PACKAGES)})")
    if not (CNI_BIN / "bridge").exists():
        missing.append(f"{CNI_BIN}/bridge (Debian: containernetworking-plugins)")
    return missing


def _used_slots() -> set[int]:
    out = subprocess.run(["ip", "-4", "-o", "addr"], capture_output=True, text=True, check=False).stdout
    return {int(m) for m in re.findall(r"inet 10\.250\.(\d+)\.\d+/", out)}


def plan(cid: str, nodes: list[dict[str, Any]], taken: set[int] | None = None) -> list[RealNodePlan]:
    """Addresses, CPU sets and memory for the real nodes ``nodes`` (their ``name``, optional ``cpuset`` CPU list,
    ``cpu`` count (default 1) and ``memory_mib``). Explicit CPU sets are checked; the others are carved from the
    highest-numbered free CPUs down (``taken``: CPUs held elsewhere, by default the exclusive cpusets of others).
    Raises :class:`RealNodeError` when the machine has not enough CPUs."""
    if not nodes:
        return []
    total = _mem_total_mib()
    for node in nodes:
        memory = node.get("memory_mib") or DEFAULT_MEMORY_MIB
        if not MIN_MEMORY_MIB <= memory <= total:
            raise RealNodeError(f"real node {node['name']!r}: memory_mib must be between {MIN_MEMORY_MIB} and this "
                                f"machine's {total}, not {memory:g}")  # fmt: skip
    slots = [s for s in range(64) if s not in _used_slots()]
    if not slots:
        raise RealNodeError("no free 10.250.S.0/24 slot for node addresses (64 clusters run?)")
    slot = slots[0]
    available = machine_cpus()
    taken = _exclusive_taken(f"continuum-{cid}-") if taken is None else taken
    used: set[int] = set()
    chosen: dict[str, tuple[int, ...]] = {}
    for node in nodes:
        if node.get("cpuset"):
            cpus = parse_cpus(node["cpuset"])
            bad = [c for c in cpus if c not in available or c in taken or c in used]
            if bad:
                held = format_cpus(taken) or "-"
                raise RealNodeError(f"real node {node['name']!r}: CPU {bad[0]} is not a free CPU of this machine "
                                    f"(CPUs {format_cpus(available)}, held exclusively: {held})")  # fmt: skip
            used.update(cpus)
            chosen[node["name"]] = tuple(cpus)
    for node in nodes:
        if node["name"] in chosen:
            continue
        need = max(1, math.ceil(node.get("cpu") or 1))
        free = [c for c in reversed(available) if c not in taken and c not in used]
        if len(free) < need:
            raise RealNodeError(f"real node {node['name']!r} needs {need} CPU(s) of its own; this machine has "
                                f"{len(free)} left (CPUs {format_cpus(available)}, in use: "
                                f"{format_cpus(taken | used) or '-'})")  # fmt: skip
        used.update(free[:need])
        chosen[node["name"]] = tuple(sorted(free[:need]))
    out = []
    for index, node in enumerate(nodes, start=1):
        out.append(RealNodePlan(
            name=node["name"], index=index, cpus=chosen[node["name"]],
            memory_mib=int(node.get("memory_mib") or DEFAULT_MEMORY_MIB),
            ip=f"10.250.{slot}.{index}", pod_subnet=f"10.{128 + slot}.{index}.0/24",
            bridge=f"cn{cid}p{index}", cgroup=f"continuum-{cid}-{node['name']}",
        ))  # fmt: skip
    return out


def _run(argv: list[str], what: str, timeout: float = 600) -> str:
    try:
        done = subprocess.run(argv, capture_output=True, text=True, timeout=timeout, check=False)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise RealNodeError(f"{what}: {exc}") from exc
    if done.returncode != 0:
        raise RealNodeError(f"{what} failed (exit {done.returncode}): {(done.stderr or done.stdout)[-1500:]}")
    return done.stdout


def build_images(bin_dir: Path) -> dict[str, str]:
    """The docker-archive tarballs of the pause and base images (built once, then cached)."""
    pause = _run(["bash", str(IMAGES_SCRIPT), "pause", str(bin_dir / "pause")], "building the pause image")
    base = _run(["bash", str(IMAGES_SCRIPT), "base"], "building continuum/base:bookworm", timeout=1800)
    return {"pause": pause.strip().splitlines()[-1], "base": base.strip().splitlines()[-1]}


# ---- host resources: the address bridge, cgroups ---------------------------------------------------------
def address_bridge(cid: str) -> str:
    return f"cn{cid}"


def add_addresses(cid: str, plans: list[RealNodePlan]) -> None:
    dev = address_bridge(cid)
    if subprocess.run(["ip", "link", "show", dev], capture_output=True, check=False).returncode != 0:
        _run(["ip", "link", "add", dev, "type", "bridge"], f"creating the bridge device {dev}")
    for p in plans:
        subprocess.run(["ip", "addr", "add", f"{p.ip}/32", "dev", dev], capture_output=True, check=False)
    _run(["ip", "link", "set", dev, "up"], f"bringing {dev} up")


def _hierarchies() -> list[Path]:
    return [d for d in CGROUPS.iterdir() if d.is_dir() and (d / "cgroup.procs").exists()]


def make_cgroups(p: RealNodePlan) -> None:
    for h in _hierarchies():
        (h / p.cgroup).mkdir(exist_ok=True)
    cpuset = CGROUPS / "cpuset" / p.cgroup
    try:
        (cpuset / "cpuset.cpus").write_text(format_cpus(p.cpus))
        (cpuset / "cpuset.mems").write_text((CGROUPS / "cpuset" / "cpuset.mems").read_text().strip())
        (cpuset / "cpuset.cpu_exclusive").write_text("1")
    except OSError as exc:
        raise RealNodeError(f"real node {p.name!r}: cannot give it CPUs {format_cpus(p.cpus)} exclusively "
                            f"({exc.strerror}: another cpuset overlaps them)") from exc  # fmt: skip
    memory = CGROUPS / "memory" / p.cgroup
    with contextlib.suppress(OSError):
        (memory / "memory.limit_in_bytes").write_text(str(p.memory_mib << 20))
    # Each exclusive set becomes a root domain of its own only once the root cpuset stops balancing across them.
    with contextlib.suppress(OSError):
        (CGROUPS / "cpuset" / "cpuset.sched_load_balance").write_text("0")


def _cgroup_pids(p: RealNodePlan) -> set[int]:
    pids: set[int] = set()
    for h in _hierarchies():
        for procs in (h / p.cgroup).rglob("cgroup.procs") if (h / p.cgroup).exists() else []:
            with contextlib.suppress(OSError, ValueError):
                pids.update(int(x) for x in procs.read_text().split())
    return pids


def remove_cgroups(p: RealNodePlan) -> None:
    """Kill what still runs in the node's cgroups, then remove them (deepest first)."""
    for _ in range(50):
        pids = _cgroup_pids(p)
        if not pids:
            break
        for pid in pids:
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.kill(pid, signal.SIGKILL)
        time.sleep(0.1)
    for h in _hierarchies():
        top = h / p.cgroup
        if not top.exists():
            continue
        for d in sorted((d for d in top.rglob("*") if d.is_dir()), key=lambda d: len(d.parts), reverse=True):
            with contextlib.suppress(OSError):
                d.rmdir()
        with contextlib.suppress(OSError):
            top.rmdir()


# ---- containerd -------------------------------------------------------------------------------------------
def node_dir(cluster: Cluster, name: str) -> Path:
    return cluster.dir / "real" / name


def socket_path(cluster: Cluster, name: str) -> Path:
    return node_dir(cluster, name) / "containerd.sock"


def containerd_config(d: Path, p: RealNodePlan, cid: str) -> str:
    return f"""version = 2
root = "{d / "containerd"}"
state = "{d / "containerd-state"}"
plugin_dir = ""
[grpc]
  address = "{d / "containerd.sock"}"
[ttrpc]
  address = "{d / "containerd.sock"}.ttrpc"
[debug]
  address = ""
[metrics]
  address = ""
[plugins."io.containerd.internal.v1.opt"]
  path = "{d / "opt"}"
[plugins."io.containerd.grpc.v1.cri"]
  sandbox_image = "{PAUSE_IMAGE}"
  stream_server_address = "127.0.0.1"
  stream_server_port = "0"
  # root here lacks CAP_SYS_RESOURCE: containerd must not try to lower a container's oom_score_adj.
  restrict_oom_score_adj = true
  enable_selinux = false
  [plugins."io.containerd.grpc.v1.cri".containerd]
    snapshotter = "overlayfs"
    default_runtime_name = "runc"
    [plugins."io.containerd.grpc.v1.cri".containerd.runtimes.runc]
      runtime_type = "io.containerd.runc.v2"
      [plugins."io.containerd.grpc.v1.cri".containerd.runtimes.runc.options]
        SystemdCgroup = false
  [plugins."io.containerd.grpc.v1.cri".cni]
    bin_dir = "{CNI_BIN}"
    conf_dir = "{d / "net.d"}"
"""


def cni_config(d: Path, p: RealNodePlan, cid: str) -> str:
    import json

    net = ipaddress.ip_network(p.pod_subnet)
    doc = {
        "cniVersion": "0.4.0",
        "name": f"continuum-{cid}-{p.index}",
        "plugins": [{
            "type": "bridge", "bridge": p.bridge, "isGateway": True, "ipMasq": False, "hairpinMode": True,
            "ipam": {"type": "host-local", "dataDir": str(d / "cni-ipam"),
                     "ranges": [[{"subnet": str(net), "gateway": str(net.network_address + 1)}]],
                     "routes": [{"dst": "0.0.0.0/0"}]},
        }],
    }  # fmt: skip
    return json.dumps(doc, indent=1)


def start_containerd(cluster: Cluster, p: RealNodePlan, cid: str, deadline: float) -> None:
    d = node_dir(cluster, p.name)
    for sub in ("containerd", "containerd-state", "net.d", "cni-ipam", "kubelet", "opt"):
        (d / sub).mkdir(parents=True, exist_ok=True)
    if len(str(d / "containerd.sock.ttrpc")) > MAX_SOCKET:
        raise RealNodeError(f"the state directory {cluster.dir} is too deep for containerd's sockets")
    (d / "containerd.toml").write_text(containerd_config(d, p, cid))
    (d / "net.d" / "10-continuum.conflist").write_text(cni_config(d, p, cid))
    name = f"containerd/{p.name}"
    cluster._spawn(name, ["containerd", "--config", str(d / "containerd.toml")])
    sock = str(d / "containerd.sock")

    def answers() -> bool:
        return subprocess.run(["ctr", "--address", sock, "version"], capture_output=True, check=False).returncode == 0

    cluster._wait(f"containerd of {p.name}", answers, deadline, [name])


def import_images(cluster: Cluster, name: str, archives: Iterable[str]) -> None:
    sock = str(socket_path(cluster, name))
    for archive in archives:
        _run(["ctr", "--address", sock, "-n", "k8s.io", "images", "import", archive],
             f"importing {Path(archive).name} into {name}'s containerd")  # fmt: skip


# ---- the kubelet ------------------------------------------------------------------------------------------
def kubelet_argv(cluster: Cluster, bin_dir: Path, p: RealNodePlan, labels: dict[str, str],
                 taints: Iterable[str]) -> list[str]:  # fmt: skip
    d = node_dir(cluster, p.name)
    sock = f"unix://{d / 'containerd.sock'}"
    ports = cluster.state["real_ports"][p.name]
    total_cpus = len(machine_cpus())
    total_mib = _mem_total_mib()
    reserved_cpu = max(0, total_cpus - len(p.cpus))
    reserved_mib = max(0, total_mib - p.memory_mib)
    argv = [
        str(bin_dir / "kubelet"), f"--kubeconfig={cluster.dir / 'kubeconfig'}", f"--root-dir={d / 'kubelet'}",
        f"--cert-dir={d / 'kubelet' / 'pki'}", f"--volume-plugin-dir={d / 'kubelet' / 'volume-plugins'}",
        f"--hostname-override={p.name}", f"--node-ip={p.ip}", f"--address={p.ip}", f"--port={ports['kubelet']}",
        "--read-only-port=0", f"--healthz-port={ports['healthz']}", "--healthz-bind-address=127.0.0.1",
        # The API (logs, exec, the debugging handlers): no anonymous access; the API server's client certificate
        # (signed by the cluster's CA) or a token the API server vouches for, each request authorised by it.
        "--anonymous-auth=false", f"--client-ca-file={cluster.dir / 'certs' / 'ca.crt'}",
        "--authentication-token-webhook", "--authorization-mode=Webhook",
        "--container-runtime=remote", f"--container-runtime-endpoint={sock}", f"--containerd={sock}",
        "--runtime-request-timeout=5m", "--cgroup-driver=cgroupfs", f"--cgroup-root=/{p.cgroup}",
        f"--kube-reserved=cpu={reserved_cpu},memory={reserved_mib}Mi", "--fail-swap-on=false", "--oom-score-adj=0",
        # The firewall is not the kubelet's to change here (no kube-proxy; KUBE-* chains would outlive the node).
        "--make-iptables-util-chains=false",
        "--eviction-hard=memory.available<50Mi,nodefs.available<1%,imagefs.available<1%",
        # The imported images are never pulled again: they must never be garbage-collected.
        "--image-gc-high-threshold=100", "--image-gc-low-threshold=99",
        f"--pod-infra-container-image={PAUSE_IMAGE}", f"--config={d / 'kubelet.yaml'}",
        f"--node-labels={','.join(f'{k}={v}' for k, v in labels.items())}", "--v=1",
    ]  # fmt: skip
    # A lease renewed every 5 s (a quarter of its duration; the default 40 s renews every 10 s, the node monitor's
    # whole grace period): only a flag-less setting goes in the file.
    (d / "kubelet.yaml").write_text(
        "apiVersion: kubelet.config.k8s.io/v1beta1\nkind: KubeletConfiguration\nnodeLeaseDurationSeconds: 20\n"
    )
    taints = list(taints)
    if taints:
        argv.append(f"--register-with-taints={','.join(taints)}")
    return argv


def _mem_total_mib() -> int:
    for line in Path("/proc/meminfo").read_text().splitlines():
        if line.startswith("MemTotal:"):
            return int(line.split()[1]) // 1024
    return 0


# ---- tear-down ----------------------------------------------------------------------------------------------
def _ctr(sock: str, *args: str) -> str:
    done = subprocess.run(["ctr", "--address", sock, "-n", "k8s.io", *args], capture_output=True, text=True,
                          timeout=60, check=False)  # fmt: skip
    return done.stdout if done.returncode == 0 else ""


def remove_containers(cluster: Cluster, name: str) -> list[str]:
    """Kill and delete every container of the node's containerd (the kubelet is gone: nobody else will); the
    network namespaces of its pod sandboxes, to unmount after."""
    import json

    sock = str(socket_path(cluster, name))
    if not Path(sock).exists():
        return []
    netns = []
    for cid in _ctr(sock, "containers", "ls", "-q").split():
        with contextlib.suppress(ValueError):
            info = json.loads(_ctr(sock, "containers", "info", cid) or "{}")
            for ns in info.get("Spec", {}).get("linux", {}).get("namespaces", []):
                if ns.get("type") == "network" and ns.get("path", "").startswith(("/var/run/netns/", "/run/netns/")):
                    netns.append(ns["path"])
        _ctr(sock, "tasks", "kill", "-a", "-s", "SIGKILL", cid)
    for cid in _ctr(sock, "containers", "ls", "-q").split():
        for _ in range(20):
            if not _ctr(sock, "tasks", "ls", "-q") or cid not in _ctr(sock, "tasks", "ls", "-q").split():
                break
            _ctr(sock, "tasks", "delete", "-f", cid)
            time.sleep(0.1)
        _ctr(sock, "containers", "delete", cid)
    return sorted(set(netns))


def kill_shims(sock: str) -> None:
    """containerd's shims outlive it; ours are the ones whose command line names our socket."""
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            cmdline = (proc / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        if cmdline and cmdline[0].endswith(b"containerd-shim-runc-v2") and sock.encode() in cmdline:
            with contextlib.suppress(ProcessLookupError):
                os.kill(int(proc.name), signal.SIGKILL)


def unmount_under(paths: Iterable[Path | str]) -> None:
    """Unmount every mount point at or below ``paths`` (deepest first; lazily if busy)."""
    prefixes = [str(Path(p)) for p in paths]
    mounts = []
    for line in Path("/proc/self/mountinfo").read_text().splitlines():
        point = line.split()[4].replace("\\040", " ")
        if any(point == p or point.startswith(p.rstrip("/") + "/") for p in prefixes):
            mounts.append(point)
    for point in sorted(set(mounts), key=len, reverse=True):
        if subprocess.run(["umount", point], capture_output=True, check=False).returncode != 0:
            subprocess.run(["umount", "-l", point], capture_output=True, check=False)


def teardown(cluster: Cluster, cid: str, plans: list[RealNodePlan]) -> None:
    """Stop every real node (kubelet, its pods, containerd) and remove what it made on the host."""
    for p in plans:
        cluster.stop_process(f"node/{p.name}")
    for p in plans:
        # /var/run is a link to /run: mountinfo names the real path.
        netns = [os.path.realpath(ns) for ns in remove_containers(cluster, p.name)]
        sock = str(socket_path(cluster, p.name))
        cluster.stop_process(f"containerd/{p.name}")
        kill_shims(sock)
        remove_cgroups(p)
        unmount_under([*netns, node_dir(cluster, p.name)])
        for ns in netns:
            with contextlib.suppress(OSError):
                os.unlink(ns)
        subprocess.run(["ip", "link", "del", p.bridge], capture_output=True, check=False)
    if plans:
        subprocess.run(["ip", "link", "del", address_bridge(cid)], capture_output=True, check=False)
