"""The host settings a local cluster changes, recorded before the first cluster of the machine starts and put back
when the last one stops (several clusters, e.g. other test sessions, may run at once).

A kubelet (real or hollow) changes the machine it runs on: at start it sets ``vm.overcommit_memory=1``,
``kernel.panic=10`` and ``kernel.panic_on_oops=1``; once ``iptables`` is installed it writes ``KUBE-*`` chains
(``KUBE-FIREWALL``...); the CNI bridge plugin turns ``net.ipv4.ip_forward`` on; real nodes' exclusive cpusets
turn the root cpuset's ``sched_load_balance`` off (see :mod:`continuum.devcluster_real`). None of that may outlive
the clusters: panic-on-oops in particular must never be left on.

The registry is ``/run/continuum-devcluster``: ``baseline.json`` (the settings as found) and one file per running
cluster naming its state directory, all under a lock. Only root can change these settings; for another user
every function here does nothing (its kubelets cannot change them either).
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import json
import os
import shlex
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

REGISTRY = Path(os.environ.get("CONTINUUM_HOST_REGISTRY", "/run/continuum-devcluster"))
#: What kubelet v1.20's setupKernelTunables sets (the last two already have its values here), and the forwarding
#: the CNI bridge plugin turns on.
SYSCTLS = (
    "vm.overcommit_memory", "vm.panic_on_oom", "kernel.panic", "kernel.panic_on_oops", "kernel.keys.root_maxkeys",
    "kernel.keys.root_maxbytes", "net.ipv4.ip_forward",
)  # fmt: skip
CPUSET_ROOT = Path("/sys/fs/cgroup/cpuset")
NETNS = Path("/run/netns")
#: Chains (and rules jumping to them) that kubelets add; only these are ever removed from the firewall.
KUBE_PREFIX = "KUBE-"


def cluster_id(state_dir: Path) -> str:
    """A short name of a cluster, derived from its state directory: names its devices, cgroups and networks."""
    return hashlib.sha256(str(state_dir.resolve()).encode()).hexdigest()[:6]


def _sysctl_path(name: str) -> Path:
    return Path("/proc/sys") / name.replace(".", "/")


def _read(path: Path) -> str | None:
    try:
        return path.read_text().strip()
    except OSError:
        return None


def _write(path: Path, value: str) -> None:
    with contextlib.suppress(OSError):
        path.write_text(value)


@contextlib.contextmanager
def _locked() -> Iterator[None]:
    REGISTRY.mkdir(mode=0o700, parents=True, exist_ok=True)
    with open(REGISTRY / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield


def _firewall_tools() -> list[str]:
    return [t for t in ("iptables", "ip6tables") if shutil.which(f"{t}-save") and shutil.which(t)]


def _save(tool: str) -> str:
    done = subprocess.run([f"{tool}-save"], capture_output=True, text=True, check=False)
    return done.stdout if done.returncode == 0 else ""


def _parse(save: str) -> dict[str, tuple[set[str], list[str]]]:
    """table -> (chains, rule lines) of an ``iptables-save`` text."""
    tables: dict[str, tuple[set[str], list[str]]] = {}
    table = ""
    for line in save.splitlines():
        if line.startswith("*"):
            table = line[1:]
            tables[table] = (set(), [])
        elif line.startswith(":") and table:
            tables[table][0].add(line[1:].split()[0])
        elif line.startswith("-A ") and table:
            tables[table][1].append(line)
    return tables


def _restore_firewall(tool: str, baseline: str) -> None:
    """Remove the ``KUBE-*`` chains and the rules that use them that the baseline did not have (nothing else:
    other software's rules added meanwhile stay)."""
    before = _parse(baseline)
    for table, (chains, rules) in _parse(_save(tool)).items():
        old_chains, old_rules = before.get(table, (set(), []))
        for rule in rules:
            if KUBE_PREFIX in rule and rule not in old_rules:
                args = shlex.split(rule)
                subprocess.run([tool, "-w", "-t", table, "-D", *args[1:]], capture_output=True, check=False)
        new = [c for c in chains if c.startswith(KUBE_PREFIX) and c not in old_chains]
        for flag in ("-F", "-X"):  # every chain flushed first: they may jump to each other
            for chain in new:
                subprocess.run([tool, "-w", "-t", table, flag, chain], capture_output=True, check=False)


def _members() -> dict[str, str]:
    out = {}
    for path in REGISTRY.glob("cluster-*"):
        out[path.name] = _read(path) or ""
    return out


def _running(state_dir: str) -> bool:
    """Whether the cluster whose state lives there still runs (one of its recorded processes is alive)."""
    try:
        state: dict[str, Any] = json.loads(Path(state_dir, "state.json").read_text())
    except (OSError, ValueError):
        return False
    for pid in state.get("pids", {}).values():
        cmdline = _read(Path(f"/proc/{pid}/cmdline"))
        if cmdline is not None and state_dir in cmdline.replace("\0", " "):
            return True
    return False


def enter(state_dir: Path) -> None:
    """Register a starting cluster; the first one on the machine records the baseline."""
    if os.geteuid() != 0:
        return
    with _locked():
        members = {k: v for k, v in _members().items() if v == str(state_dir) or _running(v)}
        baseline = REGISTRY / "baseline.json"
        if not members or not baseline.exists():
            doc = {
                "sysctl": {name: _read(_sysctl_path(name)) for name in SYSCTLS},
                "sched_load_balance": _read(CPUSET_ROOT / "cpuset.sched_load_balance"),
                "firewall": {tool: _save(tool) for tool in _firewall_tools()},
                # containerd's CRI makes /run/netns a (shared) mount point of its own for pods' network namespaces.
                "netns_mount": _is_mount(NETNS),
            }
            baseline.write_text(json.dumps(doc))
        for stale in set(_members()) - set(members):
            (REGISTRY / stale).unlink(missing_ok=True)
        (REGISTRY / f"cluster-{cluster_id(state_dir)}").write_text(str(state_dir))


def leave(state_dir: Path) -> None:
    """Unregister a stopped cluster; when no other cluster runs, put the baseline back."""
    if os.geteuid() != 0 or not REGISTRY.exists():
        return
    with _locked():
        (REGISTRY / f"cluster-{cluster_id(state_dir)}").unlink(missing_ok=True)
        others = [v for v in _members().values() if v != str(state_dir) and _running(v)]
        if others:
            _rebalance_if_unpartitioned()
            return
        baseline = REGISTRY / "baseline.json"
        try:
            doc = json.loads(baseline.read_text())
        except (OSError, ValueError):
            return
        restore(doc)
        baseline.unlink(missing_ok=True)
        for stale in _members():
            (REGISTRY / stale).unlink(missing_ok=True)


def restore(doc: dict[str, Any]) -> None:
    for name, value in doc.get("sysctl", {}).items():
        if value is not None and _read(_sysctl_path(name)) != value:
            _write(_sysctl_path(name), value)
    balance = doc.get("sched_load_balance")
    if balance == "0" and not _exclusive_children():
        # Another tool's leftover (e.g. an experiment that saved "0" while our partitions existed): with no partition
        # left, a root cpuset that does not balance leaves the whole machine unbalanced.
        balance = "1"
    if balance is not None and _read(CPUSET_ROOT / "cpuset.sched_load_balance") != balance:
        _write(CPUSET_ROOT / "cpuset.sched_load_balance", balance)
    for tool in _firewall_tools():
        _restore_firewall(tool, doc.get("firewall", {}).get(tool, ""))
    if doc.get("netns_mount") is False and _is_mount(NETNS) and not any(NETNS.iterdir()):
        subprocess.run(["umount", str(NETNS)], capture_output=True, check=False)


def _rebalance_if_unpartitioned() -> None:
    """With no real node's partition left, the root cpuset balances again even while other (hollow) clusters run:
    left off, each CPU stays a root domain of its own, and a container over both CPUs is refused SCHED_DEADLINE."""
    balance = CPUSET_ROOT / "cpuset.sched_load_balance"
    if CPUSET_ROOT.is_dir() and not _exclusive_children() and _read(balance) == "0":
        _write(balance, "1")


def _exclusive_children() -> list[Path]:
    if not CPUSET_ROOT.is_dir():
        return []
    return [d for d in CPUSET_ROOT.iterdir() if d.is_dir() and _read(d / "cpuset.cpu_exclusive") == "1"]


def _is_mount(path: Path) -> bool:
    lines = _read(Path("/proc/self/mountinfo")) or ""
    return any(line.split()[4] == str(path) for line in lines.splitlines())
