"""Super-clustering: bandwidth-aware placement of containers on cluster nodes (thesis 3.3.1, Figs. 3.27-3.28).

The four phases of Fig. 3.27, as a Kubernetes scheduler plugin chain:

1. **Sort** the queue by priority class, higher first (ties, spec proposal: the container's total
   bandwidth, descending, then natural name order).
2. **Filter** the nodes: image architecture (spec 02 section 4: a container never lands on a node whose arch
   its image lacks), taints and tolerations, required node affinity / node selector, then CPU cores, memory
   and storage still free, then RobotBoard: a container holding a driver-level (or robot-pinned) ROS node only
   on the robot's boards (Table 4.26's required "MCB; drivers" affinity, :mod:`.robot_pinning`). No node
   left: the container stays pending, each node's rejection reason kept.
3. **Score** the remaining nodes. The bandwidth rank (Eq. 3.14) of node ``n`` for container ``L`` is the
   traffic that would stay local, ``sum over containers c already bound to n of bandwidth(L, c)``;
   Eq. (3.15) normalises it to 0-100 by the best node (all 0 when every rank is 0). Other weighted policies
   add up Kubernetes-style (``total = sum of w_p * score_p``): preferred node affinity by default;
   PreferNoSchedule taints, least-allocated and balanced-allocation are available. When the best totals tie (e.g.
   all ranks 0), the **free-resource policy** picks the node with the most free CPU, then memory, then the
   first name (spec: the free-node policy is a tie-breaker, not a summed term).
4. **Bind**: reserve the resources; the container now counts as deployed for the next ranks.

Container bandwidth is Definition 3.2.1 lifted to containers: the sum of Eq. (3.12) over the ROS-node
pairs across the two containers.

:func:`default_kubernetes` is the baseline the thesis compares against (spec 9.1): same filters, queue in
priority then input order, NodeResourcesFit/LeastAllocated + NodeResourcesBalancedAllocation (+ node
affinity and taint scores), ties broken at random with a seed, like kube-scheduler. Bandwidth-blind.

Every decision keeps a :class:`~continuum.engine.core.placement.NodeVerdict` per node: the filter that rejected it
with a reason, or each policy's score and the total.

Speed (``benchmarks/superclustering_scale.py``; the previous code is the oracle of
``tests/engine/containers/test_superclustering_fast.py``): each run first indexes the workload (every
container's neighbours with the bandwidth :meth:`Workload.bw` returns, its total bandwidth) and the cluster
(capacities as arrays; the arch, taint and affinity filters and the static scores once per distinct container
requirement). A decision is then numpy over the nodes plus the container's own neighbours, in the same float
operations as the per-node code, so the same plans. The per-node verdicts are rebuilt from the bind log when
first read (:class:`_LazyVerdicts`): building 2.5 million of them was most of a 5,000 x 500 run.
"""

from __future__ import annotations

import itertools
import math
import random
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeGuard, overload

import numpy as np

from continuum.engine.containers import robot_pinning
from continuum.engine.containers.resource_model import ResourceModel
from continuum.engine.containers.resource_model import profiles as resource_profiles
from continuum.engine.containers.rosgraph import RosGraph, natural_key, pair
from continuum.engine.core import limits
from continuum.engine.core.cluster import Cluster, ClusterNode, normalize_arch
from continuum.engine.core.errors import InputError
from continuum.engine.core.placement import Decision, NodeVerdict, PlacementPlan
from continuum.engine.core.taints import Toleration, untolerated
from continuum.engine.core.unique import duplicates

__all__ = [
    "ALIASES",
    "CONTAINERS_FORMAT",
    "DEFAULT_PLATFORMS",
    "FILTERS",
    "FULL_UP_TO",
    "KUBERNETES_WEIGHTS",
    "OPERATORS",
    "POLICIES",
    "SCORERS",
    "SUPERCLUSTERING_WEIGHTS",
    "ContainerSpec",
    "FilterFn",
    "Requirement",
    "Workload",
    "bounded_plan",
    "container_bandwidth",
    "decision_verdicts",
    "default_kubernetes",
    "inter_node_bandwidth",
    "load_workload",
    "place",
    "plan_metrics",
    "superclustering",
]

CONTAINERS_FORMAT = "continuum.containers/v1"
#: Platforms assumed for an image that declares none: what the thesis builds with ``docker buildx``
#: (linux/amd64 and linux/arm64/v8, Section 4.2.1). RISC-V needs an explicit build.
DEFAULT_PLATFORMS = ("amd64", "arm64")
OPERATORS = ("In", "NotIn", "Exists", "DoesNotExist", "Gt", "Lt")
SUPERCLUSTERING_WEIGHTS = {"bandwidth": 1.0, "node_affinity": 1.0}
KUBERNETES_WEIGHTS = {"least_allocated": 1.0, "balanced_allocation": 1.0, "node_affinity": 1.0, "taint_toleration": 1.0}


# ---- container specifications ---------------------------------------------------------------------
@dataclass(frozen=True)
class Requirement:
    """One node-selector expression (Kubernetes ``matchExpressions`` item)."""

    key: str
    operator: str = "In"
    values: tuple[str, ...] = ()

    def matches(self, labels: Mapping[str, str]) -> bool:
        value = labels.get(self.key)
        if self.operator == "In":
            return value is not None and value in self.values
        if self.operator == "NotIn":
            return value is None or value not in self.values
        if self.operator == "Exists":
            return value is not None
        if self.operator == "DoesNotExist":
            return value is None
        try:  # Gt / Lt compare integers, as Kubernetes does
            return value is not None and (
                int(value) > int(self.values[0]) if self.operator == "Gt" else int(value) < int(self.values[0])
            )
        except ValueError:
            return False

    def __str__(self) -> str:
        if self.operator in ("Exists", "DoesNotExist"):
            return f"{self.key} {self.operator}"
        return f"{self.key} {self.operator} [{', '.join(self.values)}]"


@dataclass(frozen=True)
class ContainerSpec:
    name: str
    cpu: float = 0.0
    memory_mib: float = 0.0
    storage_mib: float = 0.0
    priority: float = 0
    #: Architectures the container's image is built for.
    archs: tuple[str, ...] = DEFAULT_PLATFORMS
    node_selector: Mapping[str, str] = field(default_factory=dict)
    required: tuple[Requirement, ...] = ()
    #: (weight, expressions) preferred node-affinity terms.
    preferred: tuple[tuple[float, tuple[Requirement, ...]], ...] = ()
    tolerations: tuple[Toleration, ...] = ()
    #: ROS nodes inside (informational here; bandwidth comes from the workload).
    nodes: tuple[str, ...] = ()
    #: Driver-level ROS nodes inside: reported when the container lands off the robot (robot_pinning).
    drivers: tuple[str, ...] = ()
    #: ROS nodes inside pinned to the robot's boards: the container may only go to a robot node.
    on_robot: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """This container as a ``continuum.containers/v1`` entry with every value resolved (CPU and memory
        summed from the ROS graph, ``node`` folded into the required affinity): :func:`load_workload` reads
        it back to an equal spec without the graph."""
        doc: dict[str, Any] = {
            "name": self.name,
            "nodes": list(self.nodes),
            "cpu": self.cpu,
            "memory_mib": self.memory_mib,
            "storage_mib": self.storage_mib,
            "priority": self.priority,
            "archs": list(self.archs),
        }
        if self.node_selector:
            doc["node_selector"] = dict(self.node_selector)
        for key in ("drivers", "on_robot"):
            if getattr(self, key):
                doc[key] = list(getattr(self, key))
        affinity: dict[str, Any] = {}
        if self.required:
            affinity["required"] = [_expression_dict(r) for r in self.required]
        if self.preferred:
            affinity["preferred"] = [
                {"weight": w, "match": [_expression_dict(r) for r in exprs]} for w, exprs in self.preferred
            ]
        if affinity:
            doc["affinity"] = affinity
        if self.tolerations:
            doc["tolerations"] = [
                {"key": t.key, "operator": t.operator, "value": t.value, "effect": t.effect} for t in self.tolerations
            ]
        return doc


def _expression_dict(req: Requirement) -> dict[str, Any]:
    return {"key": req.key, "operator": req.operator, "values": list(req.values)}


@dataclass
class Workload:
    """Containers to place and the bandwidth (bytes/s) between pairs of them, keyed by :func:`pair`."""

    containers: list[ContainerSpec]
    bandwidth: dict[tuple[str, str], float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        names = [c.name for c in self.containers]
        dup = sorted(duplicates(names))
        if dup:
            raise InputError(f"duplicate container name {dup[0]!r}", "containers")
        known = set(names)
        for (a, b), w in self.bandwidth.items():
            for end in (a, b):
                if end not in known:
                    raise InputError(f"bandwidth {a}-{b} refers to unknown container {end!r}", "bandwidth")
            if not (isinstance(w, (int, float)) and math.isfinite(w) and w >= 0):
                raise InputError(f"bandwidth {a}-{b} is invalid: {w!r}", "bandwidth")

    def bw(self, a: str, b: str) -> float:
        return self.bandwidth.get(pair(a, b), 0.0)

    def to_dict(self) -> dict[str, Any]:
        """The resolved ``continuum.containers/v1`` document: explicit bandwidth entries, no graph needed."""
        return {
            "format": CONTAINERS_FORMAT,
            "containers": [c.to_dict() for c in self.containers],
            "bandwidth": [
                {"a": a, "b": b, "bytes_per_s": w}
                for (a, b), w in sorted(
                    self.bandwidth.items(), key=lambda kv: (natural_key(kv[0][0]), natural_key(kv[0][1]))
                )
            ],
        }

    def total_bandwidth(self, name: str) -> float:
        return sum(w for (a, b), w in self.bandwidth.items() if name in (a, b) and a != b)


def container_bandwidth(graph: RosGraph, groups: Mapping[str, Sequence[str]], mode: str = "per_topic") -> dict:
    """Definition 3.2.1 between containers: the sum of ROS-node bandwidths across each pair of containers."""
    owner: dict[str, str] = {}
    for name, members in groups.items():
        for m in members:
            if m not in graph.nodes:
                raise InputError(f"container {name!r} names unknown ROS node {m!r}", "containers")
            if m in owner:
                raise InputError(f"ROS node {m!r} is in two containers ({owner[m]!r} and {name!r})", "containers")
            owner[m] = name
    out: dict[tuple[str, str], float] = {}
    for (a, b), w in graph.weights(mode).items():
        ca, cb = owner.get(a), owner.get(b)
        if ca is not None and cb is not None and ca != cb:
            key = pair(ca, cb)
            out[key] = out.get(key, 0.0) + w
    return out


def load_workload(
    doc: Mapping[str, Any], graph: RosGraph | None = None, model: ResourceModel | None = None
) -> Workload:
    """Read a ``continuum.containers/v1`` document (the ``cluster_ros --json`` output is accepted too).

    ``{"containers": [{"name", "nodes": [ROS nodes], "cpu", "memory_mib", "storage_mib", "priority" (or
    "priority_class", a key of the top-level "priority_classes": {name: value}),
    "archs": [...], "node": "mcb", "node_selector": {...}, "affinity": {"required": [expr],
    "preferred": [{"weight": w, "match": [expr]}]}, "tolerations": [...]}],
    "archs": [default platforms], "bandwidth": [{"a", "b", "bytes_per_s"}]}`` where ``expr`` is
    ``{"key", "operator", "values"}``. With a ROS graph, a container's missing CPU/memory are the sums over its
    ROS nodes (their requests under ``model``, the resource model's defaults when ``None``) and the bandwidth
    between containers follows Definition 3.2.1; explicit ``bandwidth`` entries override a pair.
    """
    if not isinstance(doc, Mapping):
        raise InputError("a containers document must be a JSON object")
    fmt = doc.get("format", CONTAINERS_FORMAT)
    if fmt != CONTAINERS_FORMAT:
        raise InputError(f"unsupported format {fmt!r}, expected {CONTAINERS_FORMAT!r}", "format")
    raw = doc.get("containers")
    if not isinstance(raw, list) or not raw:
        raise InputError("'containers' must be a non-empty list", "containers")
    limits.check("containers", len(raw), name="nodes")  # before any per-container work
    default_archs = _archs(doc.get("archs", list(DEFAULT_PLATFORMS)), "containers document")
    classes = doc.get("priority_classes") or {}
    if not isinstance(classes, Mapping) or not all(
        isinstance(v, (int, float)) and not isinstance(v, bool) for v in classes.values()
    ):
        raise InputError("'priority_classes' must map class names to numbers", "priority_classes")
    derived = _derived(graph, model) if graph is not None else None
    containers = [_parse_container(i, c, default_archs, graph, classes, derived) for i, c in enumerate(raw)]
    bandwidth: dict[tuple[str, str], float] = {}
    if graph is not None:
        groups = {c.name: c.nodes for c in containers if c.nodes}
        bandwidth = container_bandwidth(graph, groups)
    raw_bw = doc.get("bandwidth", [])
    if not isinstance(raw_bw, list):
        raise InputError("'bandwidth' must be a list of {a, b, bytes_per_s}", "bandwidth")
    limits.check("bandwidth", len(raw_bw), name="links")
    for i, item in enumerate(raw_bw):
        if not isinstance(item, Mapping) or not item.get("a") or not item.get("b"):
            raise InputError(f"bandwidth[{i}] needs container names 'a' and 'b'", "bandwidth")
        value = item.get("bytes_per_s")
        if value is None and "mbps" in item:
            value = item["mbps"] * 1e6 / 8 if _number(item["mbps"]) else item["mbps"]
        if not _number(value):
            raise InputError(
                f"bandwidth[{i}] ({item['a']}-{item['b']}) needs a non-negative 'bytes_per_s'", "bandwidth"
            )
        if item["a"] == item["b"]:
            raise InputError(f"bandwidth[{i}] joins container {item['a']!r} to itself", "bandwidth")
        bandwidth[pair(str(item["a"]), str(item["b"]))] = float(value)
    return Workload(containers, bandwidth)


@dataclass(frozen=True)
class _Derived:
    """What a container takes from the ROS graph: its ROS nodes' requests, drivers and pins."""

    cpu: Mapping[str, float]
    memory_mib: Mapping[str, float]
    drivers: set[str]
    on_robot: set[str]


def _derived(graph: RosGraph, model: ResourceModel | None) -> _Derived:
    profiles = resource_profiles(graph, model)
    levels = graph.levels()
    return _Derived(
        cpu={n: p.cpu for n, p in profiles.items()},
        memory_mib={n: p.memory_mib for n, p in profiles.items()},
        drivers=robot_pinning.drivers(levels),
        on_robot=robot_pinning.pinned(levels, {n: node.pin for n, node in graph.nodes.items()}),
    )


def _names_list(raw: Any, where: str, key: str) -> tuple[str, ...]:
    if not isinstance(raw, list) or not all(isinstance(n, str) for n in raw):
        raise InputError(f"{where}: '{key}' must be a list of ROS node names", "containers")
    return tuple(raw)


def _number(x: Any) -> TypeGuard[int | float]:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and x >= 0


def _archs(raw: Any, where: str) -> tuple[str, ...]:
    if isinstance(raw, str):
        raw = [raw]
    if not isinstance(raw, list) or not raw:
        raise InputError(f"{where}: 'archs' must be a non-empty list of architectures", "archs")
    return tuple(dict.fromkeys(normalize_arch(a, where) for a in raw))


def _expressions(raw: Any, where: str) -> tuple[Requirement, ...]:
    if isinstance(raw, Mapping):  # shorthand {"label": ["v1", "v2"]} or {"label": "v"}
        raw = [{"key": k, "operator": "In", "values": v if isinstance(v, list) else [v]} for k, v in raw.items()]
    if not isinstance(raw, list):
        raise InputError(f"{where} must be a list of {{key, operator, values}} expressions", "affinity")
    out = []
    for i, e in enumerate(raw):
        if not isinstance(e, Mapping) or not isinstance(e.get("key"), str) or not e["key"]:
            raise InputError(f"{where}[{i}] needs a 'key'", "affinity")
        op = e.get("operator", "In")
        if op not in OPERATORS:
            raise InputError(f"{where}[{i}] has unknown operator {op!r} (one of {', '.join(OPERATORS)})", "affinity")
        values = e.get("values", [])
        if not isinstance(values, list):
            raise InputError(f"{where}[{i}]: 'values' must be a list", "affinity")
        if op in ("In", "NotIn") and not values:
            raise InputError(f"{where}[{i}]: operator {op} needs values", "affinity")
        if op in ("Gt", "Lt") and len(values) != 1:
            raise InputError(f"{where}[{i}]: operator {op} needs exactly one value", "affinity")
        out.append(Requirement(e["key"], op, tuple(str(v) for v in values)))
    return tuple(out)


def _parse_container(
    index: int,
    raw: Any,
    default_archs: tuple[str, ...],
    graph: RosGraph | None,
    classes: Mapping[str, float],
    derived: _Derived | None = None,
) -> ContainerSpec:
    if not isinstance(raw, Mapping):
        raise InputError(f"containers[{index}] must be an object", "containers")
    name = raw.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"containers[{index}] has no string 'name'", "containers")
    where = f"container {name!r}"
    nodes = raw.get("nodes", [])
    if not isinstance(nodes, list) or not all(isinstance(n, str) for n in nodes):
        raise InputError(f"{where}: 'nodes' must be a list of ROS node names", "containers")
    if graph is not None:
        for n in nodes:
            if n not in graph.nodes:
                raise InputError(f"{where} names unknown ROS node {n!r}", "containers")
    values: dict[str, float] = {}
    for key, attr in (("cpu", "cpu"), ("memory_mib", "memory_mib"), ("storage_mib", None)):
        if raw.get(key) is not None:
            if not _number(raw[key]):
                raise InputError(f"{where} has invalid {key} {raw[key]!r}", "containers")
            values[key] = float(raw[key])
        elif derived is not None and attr is not None:  # the ROS nodes' requests (resource_model)
            values[key] = sum(getattr(derived, attr)[n] for n in nodes)
        else:
            values[key] = 0.0
    priority = raw.get("priority", 0)
    if raw.get("priority_class") is not None:
        if raw["priority_class"] not in classes:
            known = ", ".join(sorted(classes)) or "none declared"
            raise InputError(f"{where} has unknown priority_class {raw['priority_class']!r} ({known})", "containers")
        priority = classes[raw["priority_class"]]
    if isinstance(priority, bool) or not isinstance(priority, (int, float)) or not math.isfinite(priority):
        raise InputError(f"{where} has invalid priority {priority!r}", "containers")
    selector = raw.get("node_selector") or {}
    if not isinstance(selector, Mapping):
        raise InputError(f"{where}: 'node_selector' must map label keys to values", "containers")
    affinity = raw.get("affinity") or {}
    if not isinstance(affinity, Mapping):
        raise InputError(f"{where}: 'affinity' must be an object with 'required'/'preferred'", "containers")
    required = _expressions(affinity.get("required", []), f"{where} affinity.required")
    if raw.get("node"):
        required += (Requirement("kubernetes.io/hostname", "In", (str(raw["node"]),)),)
    preferred = []
    for i, term in enumerate(affinity.get("preferred", []) or []):
        if not isinstance(term, Mapping) or not _number(term.get("weight", 1)):
            raise InputError(f"{where} affinity.preferred[{i}] needs a non-negative 'weight'", "containers")
        exprs = _expressions(term.get("match", []), f"{where} affinity.preferred[{i}].match")
        preferred.append((float(term.get("weight", 1)), exprs))
    tolerations = []
    for i, t in enumerate(raw.get("tolerations", []) or []):
        tolerations.append(Toleration.parse(t, f"{where} tolerations[{i}]"))
    pins: dict[str, tuple[str, ...]] = {}
    for key in ("drivers", "on_robot"):
        if key in raw:
            pins[key] = _names_list(raw[key], where, key)
        elif derived is not None:
            pins[key] = tuple(n for n in nodes if n in getattr(derived, key))
        else:
            pins[key] = ()
    return ContainerSpec(
        name=name,
        cpu=values["cpu"],
        memory_mib=values["memory_mib"],
        storage_mib=values["storage_mib"],
        priority=int(priority) if float(priority).is_integer() else priority,
        archs=_archs(raw["archs"], where) if "archs" in raw else default_archs,
        node_selector={str(k): str(v) for k, v in selector.items()},
        required=required,
        preferred=tuple(preferred),
        tolerations=tuple(tolerations),
        nodes=tuple(nodes),
        drivers=pins["drivers"],
        on_robot=pins["on_robot"],
    )


# ---- the scheduler --------------------------------------------------------------------------------
@dataclass
class _NodeState:
    node: ClusterNode
    cpu: float = 0.0
    memory_mib: float = 0.0
    storage_mib: float = 0.0
    bound: list[str] = field(default_factory=list)

    def free(self, what: str) -> float:
        cap = getattr(self.node, what)
        return math.inf if cap is None else cap - getattr(self, what)


FilterFn = Callable[[ContainerSpec, _NodeState, float], str | None]


def _filter_arch(c: ContainerSpec, s: _NodeState, overhead: float) -> str | None:
    if s.node.arch not in c.archs:
        return f"node arch {s.node.arch} not among the image's platforms [{', '.join(c.archs)}]"
    return None


def _filter_taints(c: ContainerSpec, s: _NodeState, overhead: float) -> str | None:
    bad = untolerated(s.node.taints, c.tolerations)
    return f"taint {bad[0]} not tolerated" if bad else None


def _filter_affinity(c: ContainerSpec, s: _NodeState, overhead: float) -> str | None:
    labels = s.node.all_labels()
    for key, value in c.node_selector.items():
        if labels.get(key) != value:
            return f"node selector {key}={value} not matched ({key}={labels.get(key, '<unset>')})"
    for req in c.required:
        if not req.matches(labels):
            return f"required node affinity {req} not matched ({req.key}={labels.get(req.key, '<unset>')})"
    return None


def _filter_resources(c: ContainerSpec, s: _NodeState, overhead: float) -> str | None:
    eps = 1e-9
    for what, want, unit in (
        ("cpu", c.cpu, " cores"),
        ("memory_mib", c.memory_mib + overhead, " MiB"),
        ("storage_mib", c.storage_mib, " MiB"),
    ):
        free = s.free(what)
        if want > free + eps:
            label = what.removesuffix("_mib")
            return f"insufficient {label}: requests {want:g}{unit}, {free:g} of {getattr(s.node, what):g} free"
    return None


FILTERS: tuple[tuple[str, FilterFn], ...] = (
    ("NodeArch", _filter_arch),
    ("TaintToleration", _filter_taints),
    ("NodeAffinity", _filter_affinity),
    ("NodeResourcesFit", _filter_resources),
)


def _normalise(raw: Mapping[str, float], reverse: bool = False) -> dict[str, float]:
    """Eq. (3.15)-style: ``raw / max * 100`` (all 0 when the max is 0); ``reverse`` gives ``100 - that``."""
    top = max(raw.values(), default=0.0)
    if top <= 0:
        return dict.fromkeys(raw, 100.0 if reverse else 0.0)
    return {k: (100.0 - v / top * 100.0) if reverse else v / top * 100.0 for k, v in raw.items()}


def _fractions(c: ContainerSpec, s: _NodeState, overhead: float) -> list[float]:
    """Requested share of each limited resource (CPU, memory) after placing ``c`` on ``s``."""
    out = []
    for what, want in (("cpu", c.cpu), ("memory_mib", c.memory_mib + overhead)):
        cap = getattr(s.node, what)
        if cap:
            out.append(min(1.0, (getattr(s, what) + want) / cap))
    return out


def _score(
    policy: str, c: ContainerSpec, feasible: Sequence[_NodeState], workload: Workload, overhead: float
) -> dict[str, float]:
    if policy == "bandwidth":  # Eq. (3.14), normalised by Eq. (3.15)
        return _normalise({s.node.name: sum(workload.bw(c.name, b) for b in s.bound) for s in feasible})
    if policy == "node_affinity":
        raw = {}
        for s in feasible:
            labels = s.node.all_labels()
            raw[s.node.name] = sum(w for w, exprs in c.preferred if all(e.matches(labels) for e in exprs))
        return _normalise(raw)
    if policy == "taint_toleration":
        raw = {}
        for s in feasible:
            raw[s.node.name] = sum(
                1
                for t in s.node.taints
                if t.effect == "PreferNoSchedule" and not any(tol.tolerates(t) for tol in c.tolerations)
            )
        return _normalise(raw, reverse=True)
    if policy == "least_allocated":
        out = {}
        for s in feasible:
            fr = _fractions(c, s, overhead)
            out[s.node.name] = 100.0 * (1 - sum(fr) / len(fr)) if fr else 100.0
        return out
    if policy == "balanced_allocation":
        out = {}
        for s in feasible:
            fr = _fractions(c, s, overhead)
            mean = sum(fr) / len(fr) if fr else 0.0
            std = math.sqrt(sum((f - mean) ** 2 for f in fr) / len(fr)) if fr else 0.0
            out[s.node.name] = 100.0 * (1 - std)
        return out
    if policy == "free_resources":
        return _normalise({s.node.name: s.free("cpu") if s.node.cpu is not None else 0.0 for s in feasible})
    raise InputError(f"unknown scoring policy {policy!r} (one of {', '.join(SCORERS)})", "weights")


#: The scoring policies, in the order explanations list them.
SCORERS = ("bandwidth", "least_allocated", "balanced_allocation", "node_affinity", "taint_toleration")


def _check_weights(weights: Mapping[str, float]) -> dict[str, float]:
    out = {}
    for k, w in weights.items():
        if k not in SCORERS:
            raise InputError(f"unknown scoring policy {k!r} (one of {', '.join(SCORERS)})", "weights")
        if not _number(w):
            raise InputError(f"policy {k!r} has invalid weight {w!r}", "weights")
        out[k] = float(w)
    return out


class _Index:
    """What every decision of one run reads, computed once (the old loop recomputed it per container pair):
    each container's neighbours with the bandwidth :meth:`Workload.bw` would return, each container's total
    bandwidth, the node capacities as arrays, and the static filters and scores per distinct container
    requirement (containers of one deployment share them)."""

    def __init__(
        self, workload: Workload, cluster: Cluster, overhead: float, robot: tuple[str, str] | None = None
    ) -> None:
        self.nodes = list(cluster.nodes.values())
        self.names = [n.name for n in self.nodes]
        self.overhead = overhead
        self.label = robot or robot_pinning.ROBOT_LABEL
        self.hold = robot is not None and bool(robot_pinning.robot_nodes(cluster, self.label))
        self._robot: dict[tuple[str, ...], tuple[np.ndarray, list[str | None]]] = {}
        self._board: list[bool] | None = None
        # ``bw(a, b)`` reads only the canonical key ``pair(a, b)``; a key stored the other way round is never
        # read, so it stays out of the neighbour lists too (same values as before, not "fixed").
        self.adj: dict[str, dict[str, float]] = {}
        self.total: dict[str, float] = {}
        for (a, b), w in workload.bandwidth.items():
            if a != b:
                self.total[a] = self.total.get(a, 0) + w
                self.total[b] = self.total.get(b, 0) + w
                if pair(a, b) == (a, b):
                    self.adj.setdefault(a, {})[b] = w
                    self.adj.setdefault(b, {})[a] = w
        inf = math.inf
        self.cap = {
            what: np.array([inf if getattr(n, what) is None else getattr(n, what) for n in self.nodes], dtype=float)
            for what in _RESOURCES
        }
        self.cpu_known = np.array([n.cpu is not None for n in self.nodes])
        self.nat = np.empty(len(self.names), dtype=np.int64)  # each node's rank in natural name order
        self.nat[sorted(range(len(self.names)), key=lambda k: natural_key(self.names[k]))] = np.arange(len(self.names))
        self._static: dict[tuple, tuple[np.ndarray, list[tuple[str, str] | None]]] = {}
        self._static_rejections: dict[tuple, dict[str, list[int]]] = {}
        self._affinity: dict[tuple, np.ndarray] = {}
        self._taint: dict[tuple, np.ndarray] = {}

    def static(self, c: ContainerSpec) -> tuple[np.ndarray, list[tuple[str, str] | None]]:
        """(mask of nodes passing the arch, taint and affinity filters, per node the (filter, reason) that
        rejected it): these filters read only the node's fixed attributes."""
        key = (c.archs, c.tolerations, tuple(c.node_selector.items()), c.required)
        hit = self._static.get(key)
        if hit is None:
            reasons: list[tuple[str, str] | None] = []
            for node in self.nodes:
                s = _NodeState(node)
                for fname, fn in FILTERS[:3]:
                    reason = fn(c, s, self.overhead)
                    if reason is not None:
                        reasons.append((fname, reason))
                        break
                else:
                    reasons.append(None)
            hit = self._static[key] = (np.array([r is None for r in reasons]), reasons)
        return hit

    def static_rejections(self, c: ContainerSpec) -> dict[str, list[int]]:
        """Static filter name -> the nodes it rejects (in cluster order), cached with :meth:`static`."""
        key = (c.archs, c.tolerations, tuple(c.node_selector.items()), c.required)
        hit = self._static_rejections.get(key)
        if hit is None:
            _, reasons = self.static(c)
            hit = {}
            for k, r in enumerate(reasons):
                if r is not None:
                    hit.setdefault(r[0], []).append(k)
            self._static_rejections[key] = hit
        return hit

    def robot(self, c: ContainerSpec) -> tuple[np.ndarray, list[str | None]]:
        """(mask of nodes the RobotBoard filter lets ``c`` onto, per node its reason when not): static too,
        but it runs after the resource filter, so a full node reports resources first."""
        hit = self._robot.get(c.on_robot)
        if hit is None:
            if not self.hold or not c.on_robot:
                reasons: list[str | None] = [None] * len(self.nodes)
            else:
                if self._board is None:  # which nodes are the robot's boards: once per pass
                    self._board = [robot_pinning.is_robot(node, self.label) for node in self.nodes]
                # The reason names the container's pinned ROS nodes, not the node: one string for every node.
                reason = robot_pinning.off_board_reason(c.on_robot, self.label)
                reasons = [None if on_board else reason for on_board in self._board]
            hit = self._robot[c.on_robot] = (np.array([r is None for r in reasons]), reasons)
        return hit

    def affinity(self, c: ContainerSpec) -> np.ndarray:
        hit = self._affinity.get(c.preferred)
        if hit is None:
            raw = []
            for node in self.nodes:
                labels = node.all_labels()
                raw.append(sum(w for w, exprs in c.preferred if all(e.matches(labels) for e in exprs)))
            hit = self._affinity[c.preferred] = np.array(raw, dtype=float)
        return hit

    def taint(self, c: ContainerSpec) -> np.ndarray:
        hit = self._taint.get(c.tolerations)
        if hit is None:
            raw = [
                sum(
                    1
                    for t in node.taints
                    if t.effect == "PreferNoSchedule" and not any(tol.tolerates(t) for tol in c.tolerations)
                )
                for node in self.nodes
            ]
            hit = self._taint[c.tolerations] = np.array(raw, dtype=float)
        return hit


_RESOURCES = ("cpu", "memory_mib", "storage_mib")


def _normalise_array(raw: np.ndarray, reverse: bool = False) -> np.ndarray:
    """:func:`_normalise` over an array (the same float operations, so the same values)."""
    top = raw.max() if len(raw) else 0.0
    if top <= 0:
        return np.full(len(raw), 100.0 if reverse else 0.0)
    return 100.0 - raw / top * 100.0 if reverse else raw / top * 100.0


@dataclass
class _Evaluation:
    feasible: np.ndarray  # node indices, in cluster order
    totals: np.ndarray  # per feasible node
    shown: dict[str, np.ndarray]  # policy -> score per feasible node


class _Run:
    """One scheduling run: the live node state as Python floats (the stored values) mirrored in numpy arrays
    of free capacity (the filter), and the bind log the explanations are rebuilt from."""

    #: A copy of the committed resources every this many decisions, so one explanation replays at most
    #: this many binds.
    CHECKPOINT = 64

    def __init__(self, policy: str, index: _Index, order: list[ContainerSpec], weights: Mapping[str, float]) -> None:
        self.policy, self.index, self.order, self.weights = policy, index, order, weights
        self.states = [_NodeState(n) for n in index.nodes]
        self.free = {what: index.cap[what].copy() for what in _RESOURCES}
        self.used = {what: np.zeros(len(index.nodes)) for what in _RESOURCES}
        self.chosen: list[int | None] = []
        self.placed_at: dict[str, tuple[int, int]] = {}  # container -> (decision number, node index)
        self.checkpoints: list[dict[str, np.ndarray]] = []

    def evaluate(self, i: int, used: Mapping[str, np.ndarray], free: Mapping[str, np.ndarray]) -> _Evaluation:
        """Phases 2-3 for decision ``i`` on the given state: the feasible nodes, their scores and totals."""
        c, index = self.order[i], self.index
        eps = 1e-9
        mask, _ = index.static(c)
        mask = (
            mask
            & index.robot(c)[0]
            & ~(c.cpu > free["cpu"] + eps)
            & ~(c.memory_mib + index.overhead > free["memory_mib"] + eps)
            & ~(c.storage_mib > free["storage_mib"] + eps)
        )
        feasible = np.flatnonzero(mask)
        scores: dict[str, np.ndarray] = {}
        for p in self.weights:
            scores[p] = self._score(p, i, c, feasible, used)
        shown = dict(scores)
        if self.policy == "superclustering":
            raw = np.where(index.cpu_known, free["cpu"], 0.0)[feasible]
            shown["free_resources"] = _normalise_array(raw)
        totals: Any = 0
        for p, w in self.weights.items():
            totals = totals + w * scores[p]
        if not isinstance(totals, np.ndarray):
            totals = np.zeros(len(feasible), dtype=int)
        return _Evaluation(feasible, totals, shown)

    def _score(
        self,
        p: str,
        i: int,
        c: ContainerSpec,
        feasible: np.ndarray,
        used: Mapping[str, np.ndarray],
    ) -> np.ndarray:
        index = self.index
        if p == "bandwidth":  # Eq. (3.14): summed in bind order, as the old per-node sum over ``bound`` did
            raw = np.zeros(len(index.nodes))
            hits = []
            for other, w in index.adj.get(c.name, {}).items():
                at = self.placed_at.get(other)
                if at is not None and at[0] < i:
                    hits.append((at[0], at[1], w))
            for _, node, w in sorted(hits):
                raw[node] += w
            return _normalise_array(raw[feasible])  # Eq. (3.15)
        if p == "node_affinity":
            return _normalise_array(index.affinity(c)[feasible])
        if p == "taint_toleration":
            return _normalise_array(index.taint(c)[feasible], reverse=True)
        if p in ("least_allocated", "balanced_allocation"):
            return self._resource_score(p, c, feasible, used)
        # Any other resource-shaped policy: the per-node code itself, on the feasible nodes only.
        feasible_states = [self.state(k, used) for k in feasible]
        out = _score(p, c, feasible_states, Workload([]), index.overhead)
        return np.array([out[s.node.name] for s in feasible_states], dtype=float)

    def _resource_score(
        self, p: str, c: ContainerSpec, feasible: np.ndarray, used: Mapping[str, np.ndarray]
    ) -> np.ndarray:
        """``_score``'s least_allocated / balanced_allocation over arrays, with the same float operations in
        the same order (``sum`` from 0, ``x ** 2`` as libm's pow: ``np.power`` with an array exponent, not
        its x*x fast path, which differs in the last bit), so the same values and the same choices. The
        per-node code cost the baseline seconds at 5,000 x 500 (a node state and a list per node)."""
        fracs, has = [], []
        for what, want in (("cpu", c.cpu), ("memory_mib", c.memory_mib + self.index.overhead)):
            cap = self.index.cap[what][feasible]  # inf where the node gives none
            limited = np.isfinite(cap) & (cap != 0)  # ``if cap:`` (None or 0: not counted)
            with np.errstate(divide="ignore", invalid="ignore"):
                frac = np.minimum(1.0, (used[what][feasible] + want) / np.where(limited, cap, 1.0))
            fracs.append(np.where(limited, frac, 0.0))
            has.append(limited)
        count = has[0].astype(float) + has[1]
        total = fracs[0] + fracs[1]  # a missing part is 0.0: x + 0.0 == x, as sum() over the present ones
        with np.errstate(divide="ignore", invalid="ignore"):
            mean = np.where(count > 0, total / np.where(count > 0, count, 1.0), 0.0)
        if p == "least_allocated":
            return np.where(count > 0, 100.0 * (1 - mean), 100.0)
        two = np.full(len(feasible), 2.0)
        squares = [np.where(h, np.power(f - mean, two), 0.0) for f, h in zip(fracs, has, strict=True)]
        with np.errstate(divide="ignore", invalid="ignore"):
            std = np.where(count > 0, np.sqrt((squares[0] + squares[1]) / np.where(count > 0, count, 1.0)), 0.0)
        return 100.0 * (1 - std)

    def bind(self, i: int, k: int | None) -> None:
        if i % self.CHECKPOINT == 0:
            self.checkpoints.append({what: u.copy() for what, u in self.used.items()})
        self.chosen.append(k)
        if k is None:
            return
        c, s = self.order[i], self.states[k]
        s.cpu += c.cpu  # phase 4: bind
        s.memory_mib += c.memory_mib + self.index.overhead
        s.storage_mib += c.storage_mib
        s.bound.append(c.name)
        for what in _RESOURCES:
            self.used[what][k] = getattr(s, what)
            cap = getattr(s.node, what)
            if cap is not None:
                self.free[what][k] = cap - getattr(s, what)
        self.placed_at[c.name] = (i, k)

    def state(self, k: int, used: Mapping[str, np.ndarray]) -> _NodeState:
        """Node ``k`` with the committed resources ``used`` (float64 holds the Python floats exactly)."""
        cpu, mem, sto = (float(used[what][k]) for what in _RESOURCES)
        return _NodeState(self.index.nodes[k], cpu, mem, sto)

    def state_at(self, i: int) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
        """(committed, free) resources per node as decision ``i`` saw them: the checkpoint before it, then the
        binds since, replayed with the same additions in the same order (so the same floats)."""
        base = i - i % self.CHECKPOINT
        used = {what: u.copy() for what, u in self.checkpoints[base // self.CHECKPOINT].items()}
        for j in range(base, i):
            k = self.chosen[j]
            if k is not None:
                c = self.order[j]
                used["cpu"][k] += c.cpu
                used["memory_mib"][k] += c.memory_mib + self.index.overhead
                used["storage_mib"][k] += c.storage_mib
        free = {what: self.index.cap[what] - used[what] for what in _RESOURCES}  # inf - x = inf: no limit
        return used, free

    def verdicts(self, i: int) -> tuple[NodeVerdict, ...]:
        """Every node's verdict on decision ``i``, rebuilt on demand from the bind log."""
        used, free = self.state_at(i)
        ev = self.evaluate(i, used, free)
        c = self.order[i]
        _, static = self.index.static(c)
        at = dict(zip(ev.feasible.tolist(), range(len(ev.feasible)), strict=True))
        shown = [(p, v.tolist()) for p, v in ev.shown.items()]
        totals = ev.totals.tolist()
        out = []
        for k, name in enumerate(self.index.names):
            j = at.get(k)
            if j is not None:
                per = {p: round(v[j], 6) for p, v in shown}
                out.append(NodeVerdict(name, scores=per, total=round(totals[j], 6)))
            elif static[k] is not None:
                fname, reason = static[k]  # type: ignore[misc]
                out.append(NodeVerdict(name, rejected_by=fname, reason=reason))
            else:
                reason = _filter_resources(c, self.state(k, used), self.index.overhead)
                if reason is not None:
                    out.append(NodeVerdict(name, rejected_by="NodeResourcesFit", reason=reason))
                else:
                    out.append(NodeVerdict(name, rejected_by="RobotBoard", reason=self.index.robot(c)[1][k] or ""))
        return tuple(out)

    def bounded(self, i: int, top_k: int, examples: int) -> tuple[tuple[NodeVerdict, ...], dict[str, int]]:
        """Decision ``i`` explained in a size that does not grow with the cluster: the ``top_k`` best feasible
        nodes (the chosen one first, then by total, ties in cluster order) with the same scores as
        :meth:`verdicts`, ``examples`` rejected nodes per filter, and how many nodes each filter rejected.
        Counted on arrays (one evaluation, as the decision itself costs), not node by node."""
        used, free = self.state_at(i)
        ev = self.evaluate(i, used, free)
        c, index = self.order[i], self.index
        eps = 1e-9
        static_ok, static = index.static(c)
        robot_ok, robot_reasons = index.robot(c)
        fits = (
            ~(c.cpu > free["cpu"] + eps)
            & ~(c.memory_mib + index.overhead > free["memory_mib"] + eps)
            & ~(c.storage_mib > free["storage_mib"] + eps)
        )
        rejected = index.static_rejections(c)
        counts = {f: len(ks) for f, ks in rejected.items()}
        shown_examples = {f: ks[:examples] for f, ks in rejected.items()}
        for fname, mask in (("NodeResourcesFit", static_ok & ~fits), ("RobotBoard", static_ok & fits & ~robot_ok)):
            count = int(np.count_nonzero(mask))
            if count:
                counts[fname] = count
                shown_examples[fname] = np.flatnonzero(mask)[:examples].tolist()
        chosen = self.chosen[i]
        totals = ev.totals
        order = np.argsort(-np.asarray(totals, dtype=float), kind="stable")[: top_k + 1].tolist()
        if chosen is not None:
            j = int(np.searchsorted(ev.feasible, chosen))
            order = [j, *(o for o in order if o != j)]
        out = []
        for j in order[:top_k]:
            per = {p: round(float(v[j]), 6) for p, v in ev.shown.items()}
            out.append(NodeVerdict(index.names[int(ev.feasible[j])], scores=per, total=round(float(totals[j]), 6)))
        for fname, ks in shown_examples.items():
            for k in ks:
                if fname == "NodeResourcesFit":
                    reason = _filter_resources(c, self.state(k, used), index.overhead) or ""
                elif fname == "RobotBoard":
                    reason = robot_reasons[k] or ""
                else:
                    reason = static[k][1]  # type: ignore[index]
                out.append(NodeVerdict(index.names[k], rejected_by=fname, reason=reason))
        return tuple(out), counts


class _LazyVerdicts(Sequence[NodeVerdict]):
    """A decision's per-node verdicts, built the first time they are read: building them for every node of
    every decision was most of a large run's time and memory, and most callers read only where things went."""

    def __init__(self, run: _Run, i: int) -> None:
        self._run: _Run | None = run
        self._i = i
        self._items: tuple[NodeVerdict, ...] | None = None

    def _get(self) -> tuple[NodeVerdict, ...]:
        if self._items is None:
            assert self._run is not None
            self._items = self._run.verdicts(self._i)
            self._run = None
        return self._items

    def __len__(self) -> int:
        return len(self._run.index.nodes) if self._items is None and self._run is not None else len(self._get())

    @overload
    def __getitem__(self, k: int) -> NodeVerdict: ...
    @overload
    def __getitem__(self, k: slice) -> tuple[NodeVerdict, ...]: ...
    def __getitem__(self, k: int | slice) -> NodeVerdict | tuple[NodeVerdict, ...]:
        return self._get()[k]

    def __iter__(self) -> Iterator[NodeVerdict]:
        return iter(self._get())

    def __eq__(self, other: object) -> bool:
        if isinstance(other, (tuple, _LazyVerdicts)):
            return self._get() == tuple(other)
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return repr(self._get())


def _schedule(
    policy_name: str,
    workload: Workload,
    cluster: Cluster,
    order: list[ContainerSpec],
    weights: Mapping[str, float],
    tie_break: Callable[[_Run, np.ndarray], int],
    overhead_mib: float,
    params: dict[str, Any],
    robot: tuple[str, str] | None = robot_pinning.ROBOT_LABEL,
    index: _Index | None = None,
) -> PlacementPlan:
    """``robot``: the label of the robot's boards, to which containers holding pinned ROS nodes are held (the
    RobotBoard filter, :mod:`.robot_pinning`); ``None`` turns the constraint off. A cluster without a robot
    node cannot honour it: it is then not applied (and the off-robot drivers are reported)."""
    index = index or _Index(workload, cluster, overhead_mib, robot)
    label = index.label
    run = _Run(policy_name, index, order, weights)
    decisions: list[Decision] = []
    for i, c in enumerate(order):
        ev = run.evaluate(i, run.used, run.free)  # phases 2-3: filter, score
        if not len(ev.feasible):
            run.bind(i, None)
            decisions.append(Decision(c.name, None, None, _LazyVerdicts(run, i)))
            continue
        totals = ev.totals
        top = totals.max()
        # math.isclose(total, top, rel_tol=1e-12, abs_tol=1e-9), elementwise
        close = (totals == top) | (
            np.abs(totals - top) <= np.maximum(1e-12 * np.maximum(np.abs(totals), abs(top)), 1e-9)
        )
        best = ev.feasible[close]
        k = tie_break(run, best)
        score = round(totals[int(np.searchsorted(ev.feasible, k))].item(), 6)
        run.bind(i, k)
        decisions.append(Decision(c.name, index.names[k], score, _LazyVerdicts(run, i)))
    plan = PlacementPlan(policy_name, decisions, params=params)
    states = {s.node.name: s for s in run.states}
    plan.metrics.update(plan_metrics(plan, workload, cluster, states))
    plan.metrics["robot_nodes"] = robot_pinning.robot_nodes(cluster, label)
    plan.metrics["off_robot_drivers"] = robot_pinning.off_robot(
        plan.placed(), {c.name: c.drivers for c in workload.containers}, cluster, label
    )
    return plan


def superclustering(
    workload: Workload,
    cluster: Cluster,
    *,
    weights: Mapping[str, float] | None = None,
    overhead_mib: float = 0.0,
    drivers_on_robot: bool = True,
    robot_label: str | tuple[str, str] | None = None,
) -> PlacementPlan:
    """Place containers by super-clustering (Fig. 3.27, Eqs. 3.14-3.15) with the free-resource tie-break.

    ``overhead_mib`` is the runtime's memory cost per container (e.g. 39 MiB for K3s, Table 4.17), reserved
    on top of each container's request. ``drivers_on_robot`` holds containers with pinned (driver-level)
    ROS nodes on the nodes labelled ``robot_label`` (default ``zone=robot``; Table 4.26, :mod:`.robot_pinning`).
    """
    w = _check_weights(SUPERCLUSTERING_WEIGHTS if weights is None else weights)
    _check_overhead(overhead_mib)
    label = robot_pinning.parse_label(robot_label)
    robot = label if drivers_on_robot else None
    index = _Index(workload, cluster, overhead_mib, robot)
    order = sorted(workload.containers, key=lambda c: (-c.priority, -index.total.get(c.name, 0), natural_key(c.name)))

    def freest(run: _Run, best: np.ndarray) -> int:
        # min over (-free CPU, -free memory, natural name order), on arrays
        for what in ("cpu", "memory_mib"):
            free = run.free[what][best]
            best = best[free == free.max()]
        return int(best[np.argmin(run.index.nat[best])])

    params = {"weights": w, "tie_break": "free_resources", "overhead_mib": overhead_mib,
              "drivers_on_robot": bool(drivers_on_robot), "robot_label": "=".join(label)}  # fmt: skip
    return _schedule("superclustering", workload, cluster, order, w, freest, overhead_mib, params, robot, index)


def default_kubernetes(
    workload: Workload,
    cluster: Cluster,
    *,
    seed: int = 0,
    weights: Mapping[str, float] | None = None,
    overhead_mib: float = 0.0,
    drivers_on_robot: bool = True,
    robot_label: str | tuple[str, str] | None = None,
) -> PlacementPlan:
    """The default-Kubernetes-like baseline: least allocated + balanced allocation, random ties (seeded).
    The robot constraint is an operator's constraint (like a required affinity), so it applies here too."""
    w = _check_weights(KUBERNETES_WEIGHTS if weights is None else weights)
    _check_overhead(overhead_mib)
    order = sorted(workload.containers, key=lambda c: -c.priority)  # stable: FIFO within a priority
    rng = random.Random(seed)

    def pick(run: _Run, best: np.ndarray) -> int:
        return int(best[rng.randrange(len(best))])

    label = robot_pinning.parse_label(robot_label)
    params = {"weights": w, "tie_break": "random", "seed": seed, "overhead_mib": overhead_mib,
              "drivers_on_robot": bool(drivers_on_robot), "robot_label": "=".join(label)}  # fmt: skip
    robot = label if drivers_on_robot else None
    return _schedule("default-kubernetes", workload, cluster, order, w, pick, overhead_mib, params, robot)


def _check_overhead(overhead: float) -> None:
    if not _number(overhead):
        raise InputError(f"container overhead must be a non-negative number of MiB, got {overhead!r}", "overhead")


POLICIES: dict[str, Callable[..., PlacementPlan]] = {
    "superclustering": superclustering,
    "default-kubernetes": default_kubernetes,
}
ALIASES = {"default": "default-kubernetes", "kubernetes": "default-kubernetes", "k8s": "default-kubernetes"}


def place(policy: str, workload: Workload, cluster: Cluster, **params: Any) -> PlacementPlan:
    name = ALIASES.get(policy, policy)
    if name not in POLICIES:
        raise InputError(f"unknown placement policy {policy!r} (one of {', '.join(POLICIES)})", "policy")
    if name == "superclustering":
        params.pop("seed", None)
    return POLICIES[name](workload, cluster, **params)


#: A cluster of at most this many nodes keeps every node's verdict in a stored plan (as RT-Kube's decisions do).
FULL_UP_TO = 32


def bounded_plan(plan: PlacementPlan, top_k: int = 5, examples: int = 1) -> PlacementPlan:
    """``plan`` with each decision's explanation bounded (:meth:`_Run.bounded`): what a job stores, so a plan
    of 5,000 containers on 500 nodes is megabytes rather than the 2.5 million verdicts of every node (hundreds
    of MiB, more than a PostgreSQL jsonb value may hold). Every node's verdict stays a re-run away: the run is
    deterministic on the stored inputs (:func:`decision_verdicts`). A decision whose verdicts were already
    built (or read back from a document) is cut to the same form from them."""
    decisions = []
    for d in plan.decisions:
        lazy = d.verdicts
        if isinstance(lazy, _LazyVerdicts) and lazy._items is None and lazy._run is not None:
            verdicts, counts = lazy._run.bounded(lazy._i, top_k, examples)
        else:
            verdicts, counts = _cut(d, top_k, examples)
        decisions.append(Decision(d.item, d.node, d.score, verdicts, counts))
    return PlacementPlan(plan.policy, decisions, dict(plan.params), dict(plan.metrics))


def _cut(d: Decision, top_k: int, examples: int) -> tuple[tuple[NodeVerdict, ...], dict[str, int]]:
    if d.rejections:
        return tuple(d.verdicts), dict(d.rejections)
    scored = [v for v in d.verdicts if not v.rejected_by]
    scored.sort(key=lambda v: (v.node != d.node, -(v.total if v.total is not None else -math.inf)))
    out = scored[:top_k]
    counts: dict[str, int] = {}
    for v in d.verdicts:
        if v.rejected_by:
            counts[v.rejected_by] = counts.get(v.rejected_by, 0) + 1
            if counts[v.rejected_by] <= examples:
                out.append(v)
    return tuple(out), counts


def decision_verdicts(policy: str, workload: Workload, cluster: Cluster, item: str, **params: Any) -> Decision:
    """One decision with every node's verdict, from the inputs a plan was made from (the on-demand half of
    :func:`bounded_plan`): the same deterministic run (super-clustering; the baseline with its seed), then
    the verdicts of that one decision only. ``KeyError`` when ``item`` is not in the workload."""
    plan = place(policy, workload, cluster, **params)
    decision = plan.decision(item)
    if decision is None:
        raise KeyError(item)
    return Decision(decision.item, decision.node, decision.score, tuple(decision.verdicts))


# ---- what a plan costs on the network ---------------------------------------------------------------
def inter_node_bandwidth(placed: Mapping[str, str], workload: Workload) -> float:
    """Bytes/s between containers bound to different nodes (pending containers are not counted)."""
    return sum(w for (a, b), w in workload.bandwidth.items() if a in placed and b in placed and placed[a] != placed[b])


def plan_metrics(
    plan: PlacementPlan, workload: Workload, cluster: Cluster, states: Mapping[str, _NodeState] | None = None
) -> dict[str, Any]:
    """``inter_node_bandwidth`` (bytes/s) and its breakdown: per node the traffic crossing its boundary, per
    link the load in Mbps on the least-latency path, the bandwidth lost to pending containers, and the
    resources each node has committed."""
    placed = plan.placed()
    node_traffic = dict.fromkeys(cluster.nodes, 0.0)
    link_load: dict[tuple[str, str], float] = {}
    intra = pending_bw = 0.0
    paths: dict[str, dict[str, list[str]]] = {}
    for (a, b), w in workload.bandwidth.items():
        if a not in placed or b not in placed:
            pending_bw += w
            continue
        na, nb = placed[a], placed[b]
        if na == nb:
            intra += w
            continue
        node_traffic[na] += w
        node_traffic[nb] += w
        # Without a path (no links given) the pair itself stands for the link between the two nodes.
        if na not in paths:  # one shortest-path search per source node, not one graph per pair
            paths[na] = cluster.paths_from(na)
        hops = list(itertools.pairwise(paths[na].get(nb, []))) or [(na, nb)]
        for x, y in hops:
            key = pair(x, y)
            link_load[key] = link_load.get(key, 0.0) + w
    links = []
    for (x, y), load in sorted(link_load.items()):
        route = cluster.route(x, y)
        links.append(
            {
                "src": x,
                "dst": y,
                "load_mbps": load * 8 / 1e6,
                "bandwidth_mbps": None if route is None else route[1],
            }
        )
    metrics: dict[str, Any] = {
        "inter_node_bandwidth": inter_node_bandwidth(placed, workload),
        "intra_node_bandwidth": intra,
        "pending_bandwidth": pending_bw,
        "node_traffic": node_traffic,
        "link_load": links,
    }
    if states is not None:
        metrics["allocated"] = {
            n: {"cpu": s.cpu, "memory_mib": s.memory_mib, "storage_mib": s.storage_mib, "containers": list(s.bound)}
            for n, s in states.items()
        }
    return metrics
