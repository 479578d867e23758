"""Super-clustering as it was before the fast version (main at 0836843), kept verbatim as the oracle: the
tests compare plans on random instances and ``benchmarks/superclustering_scale.py`` times it side by side. Its
own uncached ``natural_key``/``pair`` so the reference pays what it paid before."""
# ruff: noqa
# mypy: ignore-errors

from __future__ import annotations

import itertools
import math
import random
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeGuard

from continuum.engine.containers import robot_pinning
from continuum.engine.containers.resource_model import profiles as resource_profiles
import re

from continuum.engine.containers.rosgraph import RosGraph
from continuum.engine.containers.superclustering import ContainerSpec, Requirement, Workload, _number, load_workload


def natural_key(name: str) -> tuple:
    parts = re.split(r"(\d+)", name)
    return (*(int(p) if i % 2 else p.casefold() for i, p in enumerate(parts)), name)


def pair(a: str, b: str) -> tuple[str, str]:
    return (a, b) if natural_key(a) <= natural_key(b) else (b, a)


def _bw(workload, a, b):
    return workload.bandwidth.get(pair(a, b), 0.0)


def _total_bandwidth(workload, name):
    return sum(w for (a, b), w in workload.bandwidth.items() if name in (a, b) and a != b)


from continuum.engine.core.cluster import Cluster, ClusterNode, normalize_arch
from continuum.engine.core.errors import InputError
from continuum.engine.core.placement import Decision, NodeVerdict, PlacementPlan
from continuum.engine.core.taints import Toleration, untolerated


CONTAINERS_FORMAT = "continuum.containers/v1"
#: Platforms assumed for an image that declares none: what the thesis builds with ``docker buildx``
#: (linux/amd64 and linux/arm64/v8, Section 4.2.1). RISC-V needs an explicit build.
DEFAULT_PLATFORMS = ("amd64", "arm64")
OPERATORS = ("In", "NotIn", "Exists", "DoesNotExist", "Gt", "Lt")
SUPERCLUSTERING_WEIGHTS = {"bandwidth": 1.0, "node_affinity": 1.0}
KUBERNETES_WEIGHTS = {"least_allocated": 1.0, "balanced_allocation": 1.0, "node_affinity": 1.0, "taint_toleration": 1.0}


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
        return _normalise({s.node.name: sum(_bw(workload, c.name, b) for b in s.bound) for s in feasible})
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


def _schedule(
    policy_name: str,
    workload: Workload,
    cluster: Cluster,
    order: list[ContainerSpec],
    weights: Mapping[str, float],
    tie_break: Callable[[list[_NodeState]], _NodeState],
    overhead_mib: float,
    params: dict[str, Any],
    robot: tuple[str, str] | None = robot_pinning.ROBOT_LABEL,
) -> PlacementPlan:
    """``robot``: the label of the robot's boards, to which containers holding pinned ROS nodes are held (the
    RobotBoard filter, :mod:`.robot_pinning`); ``None`` turns the constraint off. A cluster without a robot
    node cannot honour it: it is then not applied (and the off-robot drivers are reported)."""
    states = {name: _NodeState(node) for name, node in cluster.nodes.items()}
    label = robot or robot_pinning.ROBOT_LABEL
    hold = robot is not None and bool(robot_pinning.robot_nodes(cluster, label))
    decisions: list[Decision] = []
    for c in order:
        rejected: dict[str, NodeVerdict] = {}
        feasible: list[_NodeState] = []
        for name, s in states.items():  # phase 2: filter
            for fname, fn in FILTERS:
                reason = fn(c, s, overhead_mib)
                if reason is not None:
                    rejected[name] = NodeVerdict(name, rejected_by=fname, reason=reason)
                    break
            else:
                reason = robot_pinning.reject_reason(c.on_robot, s.node, label) if hold else None
                if reason is not None:
                    rejected[name] = NodeVerdict(name, rejected_by="RobotBoard", reason=reason)
                else:
                    feasible.append(s)
        if not feasible:
            decisions.append(Decision(c.name, None, None, tuple(rejected[n] for n in states)))
            continue
        scores = {p: _score(p, c, feasible, workload, overhead_mib) for p in weights}  # phase 3: score
        shown = dict(scores)
        if policy_name == "superclustering":
            shown["free_resources"] = _score("free_resources", c, feasible, workload, overhead_mib)
        totals = {s.node.name: sum(w * scores[p][s.node.name] for p, w in weights.items()) for s in feasible}
        top = max(totals.values())
        best = [s for s in feasible if math.isclose(totals[s.node.name], top, rel_tol=1e-12, abs_tol=1e-9)]
        chosen = tie_break(best)
        chosen.cpu += c.cpu  # phase 4: bind
        chosen.memory_mib += c.memory_mib + overhead_mib
        chosen.storage_mib += c.storage_mib
        chosen.bound.append(c.name)
        verdicts = []
        for name in states:
            if name in rejected:
                verdicts.append(rejected[name])
            else:
                per = {p: round(v[name], 6) for p, v in shown.items()}
                verdicts.append(NodeVerdict(name, scores=per, total=round(totals[name], 6)))
        decisions.append(Decision(c.name, chosen.node.name, round(totals[chosen.node.name], 6), tuple(verdicts)))
    plan = PlacementPlan(policy_name, decisions, params=params)
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
    order = sorted(
        workload.containers, key=lambda c: (-c.priority, -_total_bandwidth(workload, c.name), natural_key(c.name))
    )

    def freest(best: list[_NodeState]) -> _NodeState:
        return min(best, key=lambda s: (-s.free("cpu"), -s.free("memory_mib"), natural_key(s.node.name)))

    label = robot_pinning.parse_label(robot_label)
    params = {"weights": w, "tie_break": "free_resources", "overhead_mib": overhead_mib,
              "drivers_on_robot": bool(drivers_on_robot), "robot_label": "=".join(label)}  # fmt: skip
    robot = label if drivers_on_robot else None
    return _schedule("superclustering", workload, cluster, order, w, freest, overhead_mib, params, robot)


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

    def pick(best: list[_NodeState]) -> _NodeState:
        return best[rng.randrange(len(best))]

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
        hops = list(itertools.pairwise(cluster.path(na, nb))) or [(na, nb)]
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


def random_instance(n_containers: int, n_nodes: int, seed: int, degree: int = 4, noncanonical: bool = False):
    """A random workload and cluster exercising every filter and score: mixed archs, NoSchedule and
    PreferNoSchedule taints, selectors, required/preferred affinity, unlimited and tight capacities, tied
    priorities, bandwidths and node sizes (so the tie-breaks decide), and sparse container-to-container traffic."""
    from continuum.engine.core.taints import Taint

    rng = random.Random(seed)
    zones = ["a", "b", "c", "robot"]  # zone=robot: the robot's boards (RobotBoard filter)
    nodes = {}
    for k in range(n_nodes):
        name = f"node-{k}" if rng.random() < 0.8 else f"Node{k}x{rng.randrange(3)}"
        taints = []
        if rng.random() < 0.1:
            taints.append(Taint("gpu", "yes", "NoSchedule"))
        if rng.random() < 0.2:
            taints.append(Taint("spot", "", "PreferNoSchedule"))
        nodes[name] = ClusterNode(
            name,
            arch=rng.choice(["amd64", "amd64", "arm64", "riscv64"]),
            cpu=None if rng.random() < 0.05 else rng.choice([4.0, 8.0, 8.0, 16.0]),
            memory_mib=None if rng.random() < 0.05 else rng.choice([4096.0, 8192.0]),
            storage_mib=rng.choice([None, 20000.0]),
            labels={"zone": rng.choice(zones), "tier": str(rng.randrange(3))},
            taints=tuple(taints),
        )
    cluster = Cluster(nodes)
    containers = []
    for i in range(n_containers):
        sel = {"zone": rng.choice(zones)} if rng.random() < 0.1 else {}
        req = (Requirement("tier", rng.choice(["Gt", "In"]), ("0",)),) if rng.random() < 0.1 else ()
        pref = (
            ((rng.choice([1.0, 5.0]), (Requirement("zone", "In", (rng.choice(zones),)),)),)
            if rng.random() < 0.3
            else ()
        )
        tol = (Toleration("gpu", "Equal", "yes", "NoSchedule"),) if rng.random() < 0.1 else ()
        if rng.random() < 0.1:
            tol += (Toleration("spot", "Exists", "", "PreferNoSchedule"),)
        containers.append(
            ContainerSpec(
                f"c{i}",
                cpu=rng.choice([0.25, 0.5, 1.0, 2.0]),
                memory_mib=rng.choice([128.0, 256.0, 512.0]),
                storage_mib=rng.choice([0.0, 500.0]),
                priority=rng.choice([0, 0, 1, 10]),
                archs=rng.choice([("amd64", "arm64"), ("amd64",), ("amd64", "arm64", "riscv64")]),
                node_selector=sel,
                required=req,
                preferred=pref,
                tolerations=tol,
                on_robot=(f"drv{i}",) if rng.random() < 0.15 else (),
                drivers=(f"drv{i}",) if rng.random() < 0.2 else (),
            )
        )
    bandwidth: dict[tuple[str, str], float] = {}
    for i in range(n_containers):
        for _ in range(rng.randrange(degree + 1)):
            j = rng.randrange(n_containers)
            if j != i:
                key = pair(f"c{i}", f"c{j}")
                if noncanonical and rng.random() < 0.05:
                    key = (key[1], key[0])
                bandwidth[key] = rng.choice([1e3, 5e4, 1e6, 2.5e6, 1e6 / 3])
    return Workload(containers, bandwidth), cluster
