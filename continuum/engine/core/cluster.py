"""Kubernetes-level clusters: computing nodes and the network between them (``continuum.cluster/v1``).

Shared by the node-level placers (super-clustering 3.3.1, HEFT4K 3.3.2, RT-Kube 3.4). A node has an
architecture (``kubernetes.io/arch``: amd64, arm64, riscv64, ...; spec 02 section 4), allocatable CPU cores,
memory and storage in MiB (absent = not limited), labels and taints; ``rt`` (a JSON boolean), ``criticality``,
``rt_threshold`` and ``sched_rt_runtime_us``/``sched_rt_period_us`` serve the real-time placer, whose view of the
nodes (:func:`continuum.engine.rtkube.rt_model.rt_nodes`) is built from this parse; ``class`` and ``speed``
say which DAG task costs apply to it and how fast it runs them; any other key is kept in ``extra``. Links are
undirected; :meth:`Cluster.route` gives the path of least latency whose bandwidth is the path's bottleneck.

:meth:`Cluster.to_platform` (or :func:`cluster_platform`) turns the cluster into the graph G^c that HEFT4K
schedules on (thesis 3.3.2): one multi-core processor per node (cores = whole CPUs, at least 1), in Mbit and
ms (a link of B Mbit/s moves B/1000 Mbit per ms), with unlinked nodes joined over the OSPF path (least sum of
1/bandwidth, store and forward; spec 02 section 6.1) or, with ``routing="latency"``, the least-latency path.
Pairs with no path use the document's ``default_bandwidth_mbps`` / ``default_latency_ms``; without them such
transfers are free.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.core import limits
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Link, Platform, Processor
from continuum.engine.core.taints import REALTIME, STATUS_TAINTS, Taint, Toleration, untolerated

__all__ = [
    "ARCHS",
    "ARCH_ALIASES",
    "DEFAULT_RT_PERIOD_US",
    "DEFAULT_RT_RUNTIME_US",
    "FORMAT",
    "RT_FRACTION",
    "Cluster",
    "ClusterLink",
    "ClusterNode",
    "cluster_platform",
    "default_rt_threshold",
    "node_from_dict",
    "normalize_arch",
]

FORMAT = "continuum.cluster/v1"
_STATUS_KEYS = {t.key for t in STATUS_TAINTS.values()}
#: The kernel's RT bandwidth defaults (``/proc/sys/kernel/sched_rt_{runtime,period}_us``, spec 03 section 3.3).
DEFAULT_RT_RUNTIME_US = 950_000
DEFAULT_RT_PERIOD_US = 1_000_000
#: The share of a node's CPUs that real-time tasks may use by default: ``M * 0.95`` (Eq. 2.4).
RT_FRACTION = DEFAULT_RT_RUNTIME_US / DEFAULT_RT_PERIOD_US


def default_rt_threshold(
    cpu: float, runtime_us: float = DEFAULT_RT_RUNTIME_US, period_us: float = DEFAULT_RT_PERIOD_US
) -> float:
    """A node's admissible RT utilization when none is given: ``M * sched_rt_runtime_us / sched_rt_period_us``
    (``M * 0.95`` by default, computed as ``M * RT_FRACTION``)."""
    return cpu * (runtime_us / period_us)


#: Kubernetes GOARCH names; aliases below map the usual ``uname -m`` spellings onto them.
ARCHS = ("amd64", "arm64", "riscv64", "arm", "386", "ppc64le", "s390x")
ARCH_ALIASES = {
    "x86_64": "amd64",
    "x86-64": "amd64",
    "x64": "amd64",
    "aarch64": "arm64",
    "arm64/v8": "arm64",
    "armv8": "arm64",
    "riscv": "riscv64",
    "rv64": "riscv64",
    "rv64gc": "riscv64",
    "armv7": "arm",
    "armv7l": "arm",
    "arm/v7": "arm",
    "i386": "386",
    "i686": "386",
}
_KNOWN_NODE_KEYS = {
    "name", "arch", "cpu", "memory_mib", "storage_mib", "labels", "taints", "rt", "criticality", "rt_threshold",
    "class", "speed", "sched_rt_runtime_us", "sched_rt_period_us",
}  # fmt: skip


def normalize_arch(raw: Any, where: str = "architecture") -> str:
    """The Kubernetes name of an architecture (``linux/arm64/v8`` -> ``arm64``); unknown names are rejected."""
    if not isinstance(raw, str) or not raw.strip():
        raise InputError(f"{where}: architecture must be a string, got {raw!r}", "arch")
    name = raw.strip().lower()
    if name.startswith("linux/"):
        name = name[len("linux/") :]
    name = ARCH_ALIASES.get(name, name)
    if name not in ARCHS and "/" in name:
        name = ARCH_ALIASES.get(name.split("/")[0], name.split("/")[0])
    if name not in ARCHS:
        raise InputError(f"{where}: unknown architecture {raw!r} (one of {', '.join(ARCHS)})", "arch")
    return name


@dataclass(frozen=True)
class ClusterNode:
    name: str
    arch: str = "amd64"
    cpu: float | None = None
    memory_mib: float | None = None
    storage_mib: float | None = None
    labels: Mapping[str, str] = field(default_factory=dict)
    taints: tuple[Taint, ...] = ()
    rt: bool = False
    criticality: str | None = None
    rt_threshold: float | None = None
    sched_rt_runtime_us: float | None = None
    sched_rt_period_us: float | None = None
    #: The processor class DAG task costs name (besides the node's own name), and the speed factor.
    cls: str = "cpu"
    speed: float = 1.0
    extra: Mapping[str, Any] = field(default_factory=dict)
    #: Whether the document gave a ``taints`` list (RT-Kube gives an RT node without one its RealTime taint).
    taints_given: bool = False

    @property
    def effective_taints(self) -> tuple[Taint, ...]:
        """The taints every placer reads (one rule): the given ones; an RT node given none is RT-only, carrying
        RT-Kube's ``RealTime=RT:NoSchedule``."""
        return self.taints if self.taints_given else ((REALTIME,) if self.rt else ())

    def admits(self, tolerations: Iterable[Toleration] = (), now: float | None = None) -> bool:
        """Whether a pod with ``tolerations`` may be placed here: no NoSchedule/NoExecute taint left untolerated
        (:func:`~continuum.engine.core.taints.untolerated`, the filter of every placement method)."""
        return not untolerated(self.effective_taints, tolerations, now)

    @property
    def rt_capacity(self) -> float:
        """The admissible RT utilization: ``rt_threshold``, else ``M * runtime / period`` (M = 1 when unknown)."""
        if self.rt_threshold is not None:
            return self.rt_threshold
        return default_rt_threshold(
            self.cpu or 1.0,
            DEFAULT_RT_RUNTIME_US if self.sched_rt_runtime_us is None else self.sched_rt_runtime_us,
            DEFAULT_RT_PERIOD_US if self.sched_rt_period_us is None else self.sched_rt_period_us,
        )

    def all_labels(self) -> dict[str, str]:
        """The node's labels plus the well-known ones Kubernetes sets (hostname, arch, os)."""
        return {
            "kubernetes.io/hostname": self.name,
            "kubernetes.io/arch": self.arch,
            "kubernetes.io/os": "linux",
            **self.labels,
        }

    def to_dict(self) -> dict[str, Any]:
        doc: dict[str, Any] = {"name": self.name, "arch": self.arch}
        keys = ("cpu", "memory_mib", "storage_mib", "criticality", "rt_threshold", "sched_rt_runtime_us",
                "sched_rt_period_us")  # fmt: skip
        for key in keys:
            if getattr(self, key) is not None:
                doc[key] = getattr(self, key)
        if self.rt:
            doc["rt"] = True
        if self.cls != "cpu":
            doc["class"] = self.cls
        if self.speed != 1.0:
            doc["speed"] = self.speed
        if self.labels:
            doc["labels"] = dict(self.labels)
        if self.taints or self.taints_given:
            doc["taints"] = [{"key": t.key, "value": t.value, "effect": t.effect} for t in self.taints]
        doc.update(self.extra)
        return doc


@dataclass(frozen=True)
class ClusterLink:
    src: str
    dst: str
    bandwidth_mbps: float | None = None
    latency_ms: float = 0.0


@dataclass
class Cluster:
    nodes: dict[str, ClusterNode]
    links: list[ClusterLink] = field(default_factory=list)
    name: str = "cluster"
    default_bandwidth_mbps: float | None = None
    default_latency_ms: float = 0.0

    def __post_init__(self) -> None:
        if not self.nodes:
            raise InputError("a cluster needs at least one node", "nodes")
        for link in self.links:
            for end in (link.src, link.dst):
                if end not in self.nodes:
                    raise InputError(f"link {link.src}-{link.dst} refers to unknown node {end!r}", "links")
        self._routes: dict[tuple[str, str], tuple[float, float | None]] | None = None

    # ---- construction -------------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Cluster:
        if not isinstance(data, Mapping):
            raise InputError("a cluster document must be a JSON object")
        fmt = data.get("format", FORMAT)
        if fmt != FORMAT:
            raise InputError(f"unsupported format {fmt!r}, expected {FORMAT!r}", "format")
        raw_nodes = data.get("nodes")
        if not isinstance(raw_nodes, list) or not raw_nodes:
            raise InputError("'nodes' must be a non-empty list", "nodes")
        limits.check("nodes", len(raw_nodes))
        nodes: dict[str, ClusterNode] = {}
        for i, raw in enumerate(raw_nodes):
            node = node_from_dict(raw, i)
            if node.name in nodes:
                raise InputError(f"duplicate node name {node.name!r}", "nodes")
            nodes[node.name] = node
        raw_links = data.get("links", [])
        if not isinstance(raw_links, list):
            raise InputError("'links' must be a list", "links")
        limits.check("links", len(raw_links))
        links = [_parse_link(i, raw) for i, raw in enumerate(raw_links)]
        default_bw = _limit("the cluster", data, "default_bandwidth_mbps")
        if default_bw is not None and default_bw <= 0:
            raise InputError(f"default_bandwidth_mbps must be a positive number, not {default_bw!r}", "nodes")
        return cls(
            nodes,
            links,
            name=str(data.get("name") or "cluster"),
            default_bandwidth_mbps=default_bw,
            default_latency_ms=_limit("the cluster", data, "default_latency_ms") or 0.0,
        )

    def to_dict(self) -> dict[str, Any]:
        links = []
        for lk in self.links:
            item: dict[str, Any] = {"src": lk.src, "dst": lk.dst, "latency_ms": lk.latency_ms}
            if lk.bandwidth_mbps is not None:
                item["bandwidth_mbps"] = lk.bandwidth_mbps
            links.append(item)
        return {
            "format": FORMAT,
            "name": self.name,
            "nodes": [n.to_dict() for n in self.nodes.values()],
            "links": links,
        }

    # ---- network ------------------------------------------------------------------------------
    def to_platform(self, routing: str = "ospf") -> Platform:
        """The cluster graph G^c as a routed, multi-core :class:`Platform` (times in ms, data in Mbit)."""
        procs = [Processor(n.name, n.cls, n.speed, max(1, math.floor(n.cpu or 1))) for n in self.nodes.values()]
        links = [
            Link(lk.src, lk.dst, None if lk.bandwidth_mbps is None else lk.bandwidth_mbps / 1000.0, lk.latency_ms)
            for lk in self.links
        ]
        bw = None if self.default_bandwidth_mbps is None else self.default_bandwidth_mbps / 1000.0
        return Platform(procs, bandwidth=bw, latency=self.default_latency_ms, links=links, route=True, routing=routing)

    def route(self, a: str, b: str) -> tuple[float, float | None] | None:
        """(latency ms, bottleneck bandwidth Mbps or None if unlimited) between two nodes; ``None`` when
        they are not connected. The same node is (0, None). A direct link wins over any path."""
        for end in (a, b):
            if end not in self.nodes:
                raise InputError(f"unknown node {end!r}")
        if a == b:
            return (0.0, None)
        if self._routes is None:
            self._routes = self._build_routes()
        return self._routes.get((a, b))

    def _build_routes(self) -> dict[tuple[str, str], tuple[float, float | None]]:
        import networkx as nx

        g = nx.Graph()
        g.add_nodes_from(self.nodes)
        for lk in self.links:
            bw = math.inf if lk.bandwidth_mbps is None else lk.bandwidth_mbps
            if g.has_edge(lk.src, lk.dst) and g.edges[lk.src, lk.dst]["latency"] <= lk.latency_ms:
                continue
            g.add_edge(lk.src, lk.dst, latency=lk.latency_ms, bandwidth=bw)
        routes: dict[tuple[str, str], tuple[float, float | None]] = {}
        for a, paths in nx.all_pairs_dijkstra_path(g, weight="latency"):
            for b, path in paths.items():
                if a == b:
                    continue
                hops = list(itertools.pairwise(path))
                latency = sum(g.edges[x, y]["latency"] for x, y in hops)
                bottleneck = min(g.edges[x, y]["bandwidth"] for x, y in hops)
                routes[(a, b)] = (latency, None if bottleneck == math.inf else bottleneck)
        return routes

    def path(self, a: str, b: str) -> list[str]:
        """The nodes on the least-latency path from ``a`` to ``b`` (empty when not connected)."""
        return self.paths_from(a).get(b, [])

    def paths_from(self, a: str) -> dict[str, list[str]]:
        """The least-latency path from ``a`` to every node it reaches. One Dijkstra run from ``a``: the path it
        settles for ``b`` is the one a search stopped at ``b`` returns (networkx fixes a node's path when the
        node is settled), so callers asking for many pairs reuse it."""
        import networkx as nx

        g = nx.Graph()
        g.add_nodes_from(self.nodes)
        for lk in self.links:
            g.add_edge(lk.src, lk.dst, latency=lk.latency_ms)
        return nx.single_source_dijkstra_path(g, a, weight="latency")

    def schedulable(self, tolerations: Iterable[Toleration] = (), now: float | None = None) -> Cluster:
        """This cluster without the nodes a pod with ``tolerations`` may not be placed on (:meth:`ClusterNode.admits`:
        not Ready, tainted, RT-only) and their links: what the DAG schedulers, which bind pods by name and so
        bypass Kubernetes' own taint check, may use. Raises :class:`InputError` when no node is left."""
        tolerations = tuple(tolerations)
        barred = {n.name for n in self.nodes.values() if not n.admits(tolerations, now)}
        if not barred:
            return self
        nodes = {name: n for name, n in self.nodes.items() if name not in barred}
        if not nodes:
            raise InputError(f"cluster {self.name!r} has no node its pods may be placed on (all tainted, RT-only "
                             "or not Ready)", "cluster")  # fmt: skip
        links = [lk for lk in self.links if lk.src not in barred and lk.dst not in barred]
        return Cluster(nodes, links, self.name, self.default_bandwidth_mbps, self.default_latency_ms)

    def ready(self) -> Cluster:
        """This cluster without the nodes that are not Ready (those carrying a taint of
        :data:`~continuum.engine.core.taints.STATUS_TAINTS`) and their links: for the DAG schedulers, which have
        no notion of taints. Raises :class:`InputError` when no node is left."""
        down = {n.name for n in self.nodes.values() if any(t.key in _STATUS_KEYS for t in n.taints)}
        if not down:
            return self
        nodes = {name: n for name, n in self.nodes.items() if name not in down}
        if not nodes:
            raise InputError(f"cluster {self.name!r} has no Ready node", "cluster")
        links = [lk for lk in self.links if lk.src not in down and lk.dst not in down]
        return Cluster(nodes, links, self.name, self.default_bandwidth_mbps, self.default_latency_ms)

    def __len__(self) -> int:
        return len(self.nodes)


def _limit(where: str, raw: Mapping[str, Any], key: str, most: float | None = None) -> float | None:
    """``raw[key]``: a finite number from 0 to ``most`` (default ``limits.magnitude``: every figure a placer
    sums stays finite), ``None`` when absent."""
    value = raw.get(key)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
        raise InputError(f"{where} has invalid {key} {value!r}", "nodes")
    most = limits.get().magnitude if most is None else most
    if value > most:
        raise InputError(f"{where}: {key}: at most {limits._fmt(most)} (got {value!r})", "nodes")
    return float(value)


def _positive(where: str, raw: Mapping[str, Any], key: str, *, zero: bool = False) -> float | None:
    """``raw[key]`` as a positive number (or 0 with ``zero``), ``None`` when absent."""
    value = raw.get(key)
    if isinstance(value, (int, float)) and not isinstance(value, bool) and (value < 0 or (value == 0 and not zero)):
        raise InputError(f"{where}: {key} must be positive{' or 0' if zero else ''}, got {value!r}", "nodes")
    return _limit(where, raw, key)


def node_from_dict(raw: Any, index: int = 0) -> ClusterNode:
    """One node of ``continuum.cluster/v1`` (``index`` is its position, for the messages)."""
    if not isinstance(raw, Mapping):
        raise InputError(f"nodes[{index}] must be an object", "nodes")
    name = raw.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"nodes[{index}] has no string 'name'", "nodes")
    where = f"node {name!r}"
    labels = raw.get("labels") or {}
    if not isinstance(labels, Mapping):
        raise InputError(f"{where}: 'labels' must map label keys to values", "nodes")
    taints = raw.get("taints") or []
    if not isinstance(taints, list):
        raise InputError(f"{where}: 'taints' must be a list", "nodes")
    cls = raw.get("class", "cpu")
    if not isinstance(cls, str) or not cls:
        raise InputError(f"{where} has an invalid class {cls!r}", "nodes")
    cpu = _limit(where, raw, "cpu", limits.get().cores)
    if cpu == 0:
        raise InputError(f"{where} cpu must be a positive number, not 0", "nodes")
    speed = _limit(where, raw, "speed")
    if speed is not None and not limits.get().min_rate <= speed <= 1 / limits.get().min_rate:
        lim = limits.get()
        raise InputError(f"{where} speed must be from {lim.min_rate:g} to {1 / lim.min_rate:g}, not {speed!r}", "nodes")
    rt = raw.get("rt", False)
    if not isinstance(rt, bool):
        raise InputError(f"{where}: rt must be true or false (a JSON boolean), not {rt!r}", "nodes")
    rt_threshold = _positive(where, raw, "rt_threshold", zero=True)  # 0 admits no RT load
    runtime, period = _positive(where, raw, "sched_rt_runtime_us"), _positive(where, raw, "sched_rt_period_us")
    if (runtime or DEFAULT_RT_RUNTIME_US) > (period or DEFAULT_RT_PERIOD_US):
        raise InputError(f"{where}: sched_rt_runtime_us exceeds sched_rt_period_us", "nodes")
    return ClusterNode(
        name=name,
        arch=normalize_arch(raw.get("arch", "amd64"), where),
        cpu=cpu,
        memory_mib=_limit(where, raw, "memory_mib"),
        storage_mib=_limit(where, raw, "storage_mib"),
        labels={str(k): str(v) for k, v in labels.items()},
        taints=tuple(Taint.parse(t, f"{where} taints[{i}]") for i, t in enumerate(taints)),
        rt=rt,
        criticality=None if raw.get("criticality") in (None, "") else str(raw["criticality"]),
        rt_threshold=rt_threshold,
        sched_rt_runtime_us=runtime,
        sched_rt_period_us=period,
        cls=cls,
        speed=1.0 if speed is None else speed,
        extra={k: v for k, v in raw.items() if k not in _KNOWN_NODE_KEYS},
        taints_given="taints" in raw,
    )


def _parse_link(index: int, raw: Any) -> ClusterLink:
    if not isinstance(raw, Mapping) or not raw.get("src") or not raw.get("dst"):
        raise InputError(f"links[{index}] needs 'src' and 'dst' node names", "links")
    where = f"link {raw['src']}-{raw['dst']}"
    if raw["src"] == raw["dst"]:
        raise InputError(f"links[{index}] joins node {raw['src']!r} to itself", "links")
    if "bandwidth_mbps" not in raw:
        raise InputError(f"{where} has no 'bandwidth_mbps' (null means unlimited)", "links")
    bw = raw["bandwidth_mbps"]
    if bw is not None and (
        isinstance(bw, bool) or not isinstance(bw, (int, float)) or not (bw > 0 and math.isfinite(bw))
    ):
        raise InputError(f"{where} bandwidth_mbps must be a positive number or null, not {bw!r}", "links")
    lat = raw.get("latency_ms", 0.0)
    if isinstance(lat, bool) or not isinstance(lat, (int, float)) or not math.isfinite(lat) or lat < 0:
        raise InputError(f"{where} has invalid latency_ms {lat!r}", "links")
    return ClusterLink(str(raw["src"]), str(raw["dst"]), None if bw is None else float(bw), float(lat))


def cluster_platform(doc: Mapping[str, Any], routing: str = "ospf") -> Platform:
    """Read a ``continuum.cluster/v1`` document straight into the HEFT4K cluster graph."""
    return Cluster.from_dict(doc).to_platform(routing)
