"""The real-time task model of RT-Kube (thesis 2.4 and 3.4): RT containers, RT nodes, the RealTime resource.

An RT container runs one periodic ROS task ``(P, D, WCET)`` (Eq. 2.2) with a criticality class and one
WCET per node (Listing 3.33). It is valid when ``0 < WCET(n) <= D <= P`` for every node (Eq. 2.3). Its
utilization on node ``n`` is ``WCET(n) / P`` (Eq. 2.4 uses the period, as the kernel does).

Inputs are the ``continuum.rtset/v1`` contract (containers) and the ``continuum.cluster/v1`` contract
(nodes). Times stay in the unit of the input (milliseconds in the contracts); only ratios of times matter
to the scheduler, and the simulator converts to integer microseconds itself.

Readings taken where the thesis is silent (spec 03, sections 3 and 15):

* Criticality order ``NONE < A < B < C``. ``NONE`` (or a missing/null criticality) is a non-real-time
  container, which needs no period, deadline or WCET. ``D`` is rejected: it requires an ASIL-D capable
  platform (thesis 3.4).
* ``D <= P`` is required too (constrained deadlines, Eq. 2.3), not only ``WCET <= D``.
* A node with no WCET entry cannot run the container (the filter removes it).
* A node's ``rt_threshold`` defaults to ``cpu * 950000 / 1000000`` (``M * sched_rt_runtime_us /
  sched_rt_period_us``, :func:`continuum.engine.core.cluster.default_rt_threshold`); a node may give
  ``sched_rt_runtime_us``/``sched_rt_period_us`` instead.
* An RT node without an explicit ``taints`` list carries ``RealTime=RT:NoSchedule``; RT containers
  tolerate it by default, non-RT containers do not, so they never land on RT nodes.
* ``cpu`` and ``memory_mib`` are resource requests; a missing request is 0, a given one must be positive.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import yaml

from continuum.engine.core.cluster import FORMAT as CLUSTER_FORMAT
from continuum.engine.core.cluster import (
    RT_FRACTION,
    Cluster,
    ClusterNode,
)
from continuum.engine.core.cluster import node_from_dict as parse_cluster_node
from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import load_yaml_all
from continuum.engine.core.taints import REALTIME, TAINT_EFFECTS, Taint, Toleration, untolerated

__all__ = [
    "CRITICALITY_RANK",
    "NONE",
    "REALTIME_API_VERSION",
    "REALTIME_KIND",
    "RTSET_FORMAT",
    "RT_CLASSES",
    "RT_LABEL",
    "RT_SCHEDULER_NAME",
    "RT_TAINT",
    "RT_TOLERATION",
    "TAINT_EFFECTS",
    "RTContainer",
    "RTNode",
    "Taint",
    "Toleration",
    "cluster_from_dict",
    "cluster_to_dict",
    "container_from_dict",
    "default_tolerations",
    "deployment_manifest",
    "node_from_dict",
    "parse_criticality",
    "realtime_from_dict",
    "realtime_from_yaml",
    "realtime_resource",
    "realtime_to_yaml",
    "rt_node",
    "rt_nodes",
    "rtset_from_dict",
    "rtset_to_dict",
    "untolerated",
]

RTSET_FORMAT = "continuum.rtset/v1"
REALTIME_API_VERSION = "rt.scheduling/v1"
REALTIME_KIND = "RealTime"
#: Pod label that links a Deployment's pods to their RealTime resource (Listing 3.33, line 30).
RT_LABEL = "rt-scheduling"
RT_SCHEDULER_NAME = "RT-scheduler"

NONE = "NONE"
#: Criticality rank, lowest to highest (spec 03, conventions).
CRITICALITY_RANK = {NONE: 0, "A": 1, "B": 2, "C": 3}
RT_CLASSES = ("A", "B", "C")


RT_TAINT = REALTIME
RT_TOLERATION = Toleration("RealTime", "Equal", "RT", "NoSchedule")


# ---- containers ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RTContainer:
    """One containerized task; ``criticality == "NONE"`` is a standard (non-RT) container."""

    name: str
    criticality: str = NONE
    period: float | None = None
    deadline: float | None = None
    wcet: Mapping[str, float] = field(default_factory=dict)
    stateless: bool = False
    cpu: float = 0.0
    memory_mib: float = 0.0
    tolerations: tuple[Toleration, ...] = ()
    #: Creation order/time, the queue's tie-break (input order when not given).
    arrival: float = 0.0

    @property
    def is_rt(self) -> bool:
        return self.criticality != NONE

    @property
    def rank(self) -> int:
        return CRITICALITY_RANK[self.criticality]

    def utilization(self, node: str) -> float | None:
        """``WCET(node) / P`` (Eq. 2.4 term); ``None`` when the container has no WCET for that node."""
        if not self.is_rt or self.period is None or node not in self.wcet:
            return None
        return self.wcet[node] / self.period

    def timing(self) -> tuple[float, float]:
        """``(P, D)`` of an RT container; a standard container has neither (ValueError)."""
        if self.period is None or self.deadline is None:
            raise ValueError(f"container {self.name!r} is not a real-time container")
        return self.period, self.deadline

    def max_utilization(self) -> float:
        if not self.is_rt or self.period is None:
            return 0.0
        period = self.period
        return max((w / period for w in self.wcet.values()), default=0.0)

    def to_dict(self) -> dict[str, Any]:
        doc: dict[str, Any] = {"name": self.name, "criticality": self.criticality}
        if self.is_rt:
            doc.update(period=self.period, deadline=self.deadline, wcet=dict(self.wcet))
        doc.update(stateless=self.stateless, cpu=self.cpu, memory_mib=self.memory_mib)
        if self.tolerations != (default_tolerations(self.criticality)):
            doc["tolerations"] = [t.to_dict() for t in self.tolerations]
        doc["arrival"] = self.arrival
        return doc


def default_tolerations(criticality: str) -> tuple[Toleration, ...]:
    """RT pods carry the RealTime toleration (Listing 3.33, lines 38-42); standard pods carry none."""
    return (RT_TOLERATION,) if criticality != NONE else ()


def parse_criticality(raw: Any, where: str, *, allow_none: bool = True) -> str:
    if raw is None or raw == "" or (isinstance(raw, str) and raw.upper() == NONE):
        if allow_none:
            return NONE
        raise InputError(f"{where}: criticality is required (A, B or C)", "criticality")
    if not isinstance(raw, str):
        raise InputError(f"{where}: criticality {raw!r} is not a string", "criticality")
    value = raw.strip().upper()
    if value == "D":
        raise InputError(f"{where}: criticality D requires ASIL-D capable platform (supported: A, B, C)", "criticality")
    if value not in RT_CLASSES:
        raise InputError(f"{where}: unsupported criticality {raw!r} (supported: A, B, C, NONE)", "criticality")
    return value


def container_from_dict(raw: Any, index: int, known_nodes: Iterable[str] | None = None) -> RTContainer:
    """One entry of ``continuum.rtset/v1`` ``containers``; validates Eq. 2.3 for every node."""
    if not isinstance(raw, Mapping):
        raise InputError(f"containers[{index}]: must be an object", "containers")
    name = raw.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"containers[{index}]: name is required", "name")
    where = f"container {name!r}"
    crit = parse_criticality(raw.get("criticality"), where)
    stateless = raw.get("stateless", False)
    if not isinstance(stateless, bool):
        raise InputError(f"{where}: stateless must be true or false", "stateless")
    cpu = _request(raw, "cpu", where)
    mem = _request(raw, "memory_mib", where)
    arrival = _number(raw.get("arrival", float(index)), f"{where}: arrival", "arrival")
    tolerations = default_tolerations(crit)
    if "tolerations" in raw:
        if not isinstance(raw["tolerations"], list):
            raise InputError(f"{where}: tolerations must be a list", "tolerations")
        tolerations = tuple(Toleration.parse(t, where) for t in raw["tolerations"])
    if crit == NONE:
        return RTContainer(name, NONE, stateless=stateless, cpu=cpu, memory_mib=mem, tolerations=tolerations,
                           arrival=arrival)  # fmt: skip
    period = _positive(raw.get("period"), f"{where}: period", "period")
    deadline = _positive(raw.get("deadline"), f"{where}: deadline", "deadline")
    if deadline > period:
        raise InputError(f"{where}: deadline {deadline:g} exceeds period {period:g} (needs D <= P)", "deadline")
    wcet_raw = raw.get("wcet")
    if not isinstance(wcet_raw, Mapping) or not wcet_raw:
        raise InputError(f"{where}: wcet must map at least one node to its WCET", "wcet")
    wcet = _wcet_fast(wcet_raw, deadline)
    if wcet is None:  # something is wrong: the value-by-value check names the first bad one
        wcet = {}
        for node, value in wcet_raw.items():
            w = _positive(value, f"{where}: wcet on node {node!r}", "wcet")
            if w > deadline:
                raise InputError(f"{where}: wcet {w:g} on node {node!r} exceeds deadline {deadline:g}", "wcet")
            wcet[str(node)] = w
    if known_nodes is not None:
        # A set given by the caller is used as it is: rtset_from_dict builds one for all its containers.
        known = known_nodes if isinstance(known_nodes, set | frozenset) else set(known_nodes)
        if not known.issuperset(wcet):
            unknown = sorted(n for n in wcet if n not in known)
            raise InputError(f"{where}: wcet names unknown node {unknown[0]!r}", "wcet")
    return RTContainer(name, crit, period, deadline, wcet, stateless, cpu, mem, tolerations, arrival)


def rtset_from_dict(doc: Any, known_nodes: Iterable[str] | None = None) -> list[RTContainer]:
    """Read ``continuum.rtset/v1``; with ``known_nodes``, every WCET must name one of them."""
    if not isinstance(doc, Mapping):
        raise InputError("RT set: expected a JSON object", "format")
    fmt = doc.get("format", RTSET_FORMAT)
    if fmt != RTSET_FORMAT:
        raise InputError(f"RT set: format {fmt!r} is not {RTSET_FORMAT}", "format")
    raw = doc.get("containers")
    if not isinstance(raw, list):
        raise InputError("RT set: containers must be a list", "containers")
    known = None if known_nodes is None else frozenset(known_nodes)
    containers = [container_from_dict(c, i, known) for i, c in enumerate(raw)]
    seen: set[str] = set()
    for c in containers:
        if c.name in seen:
            raise InputError(f"container {c.name!r}: duplicate name", "name")
        seen.add(c.name)
    return containers


def rtset_to_dict(containers: Iterable[RTContainer]) -> dict[str, Any]:
    return {"format": RTSET_FORMAT, "containers": [c.to_dict() for c in containers]}


# ---- nodes ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RTNode:
    name: str
    rt: bool = False
    #: ``"C"`` or another class (``"A"``/``"B"``) or ``None``; only "C or not C" matters (Alg. 3, XOR).
    criticality: str | None = None
    cpu: float = 1.0
    memory_mib: float = math.inf
    rt_threshold: float = RT_FRACTION
    taints: tuple[Taint, ...] = ()
    labels: Mapping[str, str] = field(default_factory=dict)

    @property
    def is_c_node(self) -> bool:
        return self.criticality == "C"

    def with_taint(self, taint: Taint) -> RTNode:
        return replace(self, taints=(*self.taints, taint))


def rt_node(node: ClusterNode) -> RTNode:
    """RT-Kube's view of one parsed ``continuum.cluster/v1`` node (spec 03, section 3.3).

    A node with no ``cpu`` counts as one core and one with no ``memory_mib`` is not limited by memory
    requests; the threshold is :attr:`ClusterNode.rt_capacity`; an RT node without an explicit ``taints``
    list carries ``RealTime=RT:NoSchedule``; a criticality must be A, B or C.
    """
    where = f"node {node.name!r}"
    crit = None if node.criticality in (None, "") else parse_criticality(node.criticality, where, allow_none=False)
    taints = node.effective_taints
    return RTNode(
        node.name,
        node.rt,
        crit,
        1.0 if node.cpu is None else node.cpu,
        math.inf if node.memory_mib is None else node.memory_mib,
        node.rt_capacity,
        tuple(taints),
        dict(node.labels),
    )


def rt_nodes(cluster: Cluster) -> list[RTNode]:
    """RT-Kube's view of a parsed cluster: its nodes in document order (links are irrelevant to RT-Kube)."""
    return [rt_node(n) for n in cluster.nodes.values()]


def node_from_dict(raw: Any, index: int) -> RTNode:
    """One node of ``continuum.cluster/v1`` with the RT attributes (parsed by :mod:`continuum.engine.core.cluster`)."""
    return rt_node(parse_cluster_node(raw, index))


def cluster_from_dict(doc: Any) -> list[RTNode]:
    """The RT nodes of a ``continuum.cluster/v1`` document, read by the one parser of the format
    (:meth:`continuum.engine.core.cluster.Cluster.from_dict`)."""
    return rt_nodes(Cluster.from_dict(doc))


def cluster_to_dict(nodes: Iterable[RTNode]) -> dict[str, Any]:
    out = []
    for n in nodes:
        doc: dict[str, Any] = {"name": n.name, "cpu": n.cpu, "rt": n.rt, "rt_threshold": n.rt_threshold,
                               "taints": [str(t) if t.until is None else t.to_dict() for t in n.taints]}  # fmt: skip
        if n.memory_mib < math.inf:
            doc["memory_mib"] = n.memory_mib
        if n.criticality:
            doc["criticality"] = n.criticality
        if n.labels:
            doc["labels"] = dict(n.labels)
        out.append(doc)
    return {"format": CLUSTER_FORMAT, "nodes": out}


# ---- the RealTime resource (Listing 3.33) ----------------------------------------------------------------
def realtime_resource(container: RTContainer, namespace: str | None = None) -> dict[str, Any]:
    """The ``RealTime`` object of Listing 3.33 for one RT container, with the listing's exact field names.

    [PROPOSAL] The listing has no place for the container's stateless flag and resource requests; they go
    to the optional ``spec.stateless``, ``spec.cpu`` (cores) and ``spec.memoryMib``, written only when set.
    """
    if not container.is_rt:
        raise InputError(f"container {container.name!r}: a non-RT container has no RealTime resource", "criticality")
    metadata: dict[str, Any] = {"name": container.name}
    if namespace:
        metadata["namespace"] = namespace
    spec: dict[str, Any] = {
        "criticality": container.criticality,
        "rtPeriod": _plain(container.period),
        "rtDeadline": _plain(container.deadline),
        "rtWcets": [{"node": node, "rtWcet": _plain(w)} for node, w in container.wcet.items()],
    }
    # [PROPOSAL] extension fields, written only when they differ from the default so that the listing's
    # objects stay exactly the listing.
    if container.stateless:
        spec["stateless"] = True
    if container.cpu:
        spec["cpu"] = _plain(container.cpu)
    if container.memory_mib:
        spec["memoryMib"] = _plain(container.memory_mib)
    return {"apiVersion": REALTIME_API_VERSION, "kind": REALTIME_KIND, "metadata": metadata, "spec": spec}


def realtime_to_yaml(containers: Iterable[RTContainer], namespace: str | None = None) -> str:
    """RealTime resources as a multi-document YAML stream (key order as in the listing)."""
    docs = [realtime_resource(c, namespace) for c in containers if c.is_rt]
    return yaml.safe_dump_all(docs, sort_keys=False, default_flow_style=False)


def realtime_from_dict(doc: Any, index: int = 0, known_nodes: Iterable[str] | None = None) -> RTContainer:
    """An RT container from one ``RealTime`` object; the same validation as the rtset reader."""
    if not isinstance(doc, Mapping):
        raise InputError(f"document {index}: must be a mapping", "kind")
    if doc.get("apiVersion") != REALTIME_API_VERSION or doc.get("kind") != REALTIME_KIND:
        raise InputError(f"document {index}: expected apiVersion {REALTIME_API_VERSION}, kind {REALTIME_KIND}", "kind")
    meta = doc.get("metadata")
    name = meta.get("name") if isinstance(meta, Mapping) else None
    if not isinstance(name, str) or not name:
        raise InputError(f"document {index}: metadata.name is required", "metadata.name")
    spec = doc.get("spec")
    where = f"RealTime {name!r}"
    if not isinstance(spec, Mapping):
        raise InputError(f"{where}: spec is required", "spec")
    for key in ("criticality", "rtPeriod", "rtDeadline", "rtWcets"):
        if key not in spec:
            raise InputError(f"{where}: spec.{key} is required", key)
    crit = parse_criticality(spec["criticality"], where, allow_none=False)
    wcets = spec["rtWcets"]
    if not isinstance(wcets, list) or not wcets:
        raise InputError(f"{where}: spec.rtWcets needs at least one entry", "rtWcets")
    wcet: dict[str, Any] = {}
    for i, entry in enumerate(wcets):
        if not isinstance(entry, Mapping) or not isinstance(entry.get("node"), str) or "rtWcet" not in entry:
            raise InputError(f"{where}: spec.rtWcets[{i}] needs node and rtWcet", "rtWcets")
        if entry["node"] in wcet:
            raise InputError(f"{where}: node {entry['node']!r} appears twice in spec.rtWcets", "rtWcets")
        wcet[entry["node"]] = entry["rtWcet"]
    flat = {"name": name, "criticality": crit, "period": spec["rtPeriod"], "deadline": spec["rtDeadline"],
            "wcet": wcet, "stateless": spec.get("stateless", False), "cpu": spec.get("cpu"),
            "memory_mib": spec.get("memoryMib")}  # fmt: skip
    try:
        return container_from_dict(flat, index, known_nodes)
    except InputError as exc:
        raise InputError(str(exc).replace(f"container {name!r}", where, 1), exc.field) from exc


def realtime_from_yaml(text: str, known_nodes: Iterable[str] | None = None) -> list[RTContainer]:
    """Every ``RealTime`` document of a YAML stream; other kinds (the Deployment of Listing 3.33) are skipped."""
    docs = load_yaml_all(text, "yaml")
    known = None if known_nodes is None else list(known_nodes)
    out = [
        realtime_from_dict(d, i, known)
        for i, d in enumerate(docs)
        if isinstance(d, Mapping) and d.get("kind") == REALTIME_KIND
    ]
    if not out:
        raise InputError("no RealTime document in the YAML stream", "kind")
    return out


def deployment_manifest(container: RTContainer, image: str, replicas: int = 1) -> dict[str, Any]:
    """The Deployment that uses a RealTime resource (Listing 3.33, lines 15-42)."""
    labels = {"app": container.name}
    pod_labels = dict(labels)
    if container.is_rt:
        pod_labels[RT_LABEL] = container.name
    if container.stateless:
        # spec 03 section 5.4 [PROPOSAL]: only pods labelled stateless may be evicted by the monitor.
        pod_labels["rt.monitoring/stateless"] = "true"
    pod_spec: dict[str, Any] = {"containers": [{"name": container.name, "image": image}]}
    requests = {}
    if container.cpu:
        requests["cpu"] = f"{round(container.cpu * 1000)}m"
    if container.memory_mib:
        requests["memory"] = f"{round(container.memory_mib)}Mi"
    if requests:
        pod_spec["containers"][0]["resources"] = {"requests": requests}
    if container.is_rt:
        pod_spec["schedulerName"] = RT_SCHEDULER_NAME
    if container.tolerations:
        pod_spec["tolerations"] = [t.to_dict() for t in container.tolerations]
    return {
        "apiVersion": "apps/v1",
        "kind": "Deployment",
        "metadata": {"name": f"{container.name}-deployment", "labels": labels},
        "spec": {
            "replicas": replicas,
            "selector": {"matchLabels": labels},
            "template": {"metadata": {"labels": pod_labels}, "spec": pod_spec},
        },
    }


# ---- helpers ---------------------------------------------------------------------------------------------------
def _number(value: Any, what: str, field_name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise InputError(f"{what} must be a finite number, got {value!r}", field_name)
    return float(value)


def _positive(value: Any, what: str, field_name: str) -> float:
    if value is None:
        raise InputError(f"{what} is required", field_name)
    v = _number(value, what, field_name)
    if v <= 0:
        raise InputError(f"{what} must be positive, got {value!r}", field_name)
    return v


def _wcet_fast(raw: Mapping[Any, Any], deadline: float) -> dict[str, float] | None:
    """The WCET map as floats when every value is a finite number in (0, deadline], else ``None``: the
    checks of ``_positive`` on all values at once with C-level builtins (a WCET per node of a 5,000-node
    cluster for each of 1,000 containers is 5 M values: one Python call each cost seconds)."""
    values = list(raw.values())
    types = set(map(type, values))
    if not types <= {float, int}:  # bool is not int here: type() is exact
        return None
    floats = values if types == {float} else list(map(float, values))
    total = sum(floats)  # NaN or an infinity anywhere makes it non-finite
    if not math.isfinite(total) or min(floats) <= 0 or max(floats) > deadline:
        return None
    if set(map(type, raw)) == {str}:
        if floats is values and type(raw) is dict:
            # Already str -> float: the parsed document's own dict (read-only from here on), not a copy of
            # millions of entries (a third of the command's peak memory at 5,000 nodes x 1,000 containers).
            return raw
        return dict(zip(raw, floats, strict=True))
    return dict(zip(map(str, raw), floats, strict=True))


def _request(raw: Mapping[str, Any], key: str, where: str) -> float:
    if raw.get(key) is None:
        return 0.0
    return _positive(raw[key], f"{where}: {key}", key)


def _plain(x: float | None) -> int | float | None:
    """Write 100.0 as 100 so the YAML reads like the listing."""
    if x is not None and float(x).is_integer():
        return int(x)
    return x
