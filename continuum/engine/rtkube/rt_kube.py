"""RT-Kube's secondary real-time scheduler (thesis 3.4, Fig. 3.34, Algorithms 3-4, Eqs. 2.4, 3.17-3.18).

Four phases, one container at a time:

1. **Sort** -- a "hierarchical" priority queue: criticality ``C > B > A > NONE``. The thesis gives no
   tie-break; we follow Kubernetes' own queue sort (earlier creation first, then name). Spec 03 proposes
   "higher utilization first" instead: ``sort_tiebreak="utilization"``.
2. **Filter** -- the default Kubernetes filters RT-Kube keeps (taints/tolerations, resource requests) and
   Algorithm 3: an RT container only goes to an RT node that has a WCET for it, whose projected RT
   utilization ``newUT = currentUT + WCET(n)/P`` does not exceed ``thresholdUT = M * 0.95`` (Eq. 2.4,
   equality passes), and whose class matches the container's by the XOR rule
   ``(x is C) xor (n is C)`` => removed.
3. **Score** -- Algorithm 4 over ``nRank = (thresholdUT - newUT) / thresholdUT``: ``A: 1 - nRank`` (pack),
   ``C: nRank`` (spread), ``B: h(nRank)`` if ``nRank <= 1/K`` else ``g(nRank)`` (Eq. 3.18) with the
   thesis' ``K = 2, h(z) = z/5 + 9/10, g(z) = 5/3 z^2 - 9/2 z + 17/6`` (Fig. 3.35) as defaults.
   Non-RT containers get Kubernetes' default ``LeastAllocated`` score. Ties go to the lowest node name
   (real Kubernetes picks at random among ties; we stay deterministic).
4. **Bind** -- reserve the utilization and requests in the :class:`Ledger`, so later containers of the
   same pass see them. A container no node passes stays pending with every node's reason.

[AMBIGUOUS] (spec 03 #2) Eq. 3.18 applies h/g to the free capacity ``nRank``, while the prose ("K -> 1-
makes B resemble A") suggests the normalized load ``1 - nRank``. ``b_score_argument="free"`` (default) is
the literal equation, ``"load"`` the prose's reading.

:func:`kube_default` is the RT-unaware baseline the thesis compares against ("Native K3S"): only taints,
resource requests and ``LeastAllocated``, ties broken at random as kube-scheduler does.
"""

from __future__ import annotations

import functools
import math
import random
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.core.errors import InputError
from continuum.engine.core.placement import Decision, NodeVerdict, PlacementPlan
from continuum.engine.rtkube.rt_model import RTContainer, RTNode, Taint, Toleration, untolerated

__all__ = [
    "ADMISSION_EPS",
    "Binding",
    "Curve",
    "Filtered",
    "Ledger",
    "RTKubeParams",
    "b_curve",
    "explain",
    "kube_default",
    "kube_score",
    "least_allocated",
    "n_rank",
    "node_verdict",
    "place_one",
    "placements_by_node",
    "rt_filter",
    "rt_score",
    "schedule",
    "sort_queue",
]

#: Relative slack of the admission comparison, so that 8 x 0.95 == 7.6 passes despite float rounding.
ADMISSION_EPS = 1e-9

Curve = Sequence[float] | Callable[[float], float]


@dataclass(frozen=True)
class RTKubeParams:
    """Tunables of Algorithm 4 / Eq. 3.18 and of the queue; defaults are the thesis' (Fig. 3.35)."""

    k: float = 2.0
    #: h and g as polynomial coefficients, highest power first, or as callables.
    h: Curve = (1 / 5, 9 / 10)
    g: Curve = (5 / 3, -9 / 2, 17 / 6)
    b_score_argument: str = "free"
    sort_tiebreak: str = "arrival"
    check_resources: bool = True

    def __post_init__(self) -> None:
        if not (isinstance(self.k, int | float) and self.k > 0):
            raise InputError(f"K must be positive, got {self.k!r}", "k")
        if self.b_score_argument not in ("free", "load"):
            raise InputError(
                f"b_score_argument must be free or load, got {self.b_score_argument!r}", "b_score_argument"
            )
        if self.sort_tiebreak not in ("arrival", "utilization"):
            raise InputError(
                f"sort_tiebreak must be arrival or utilization, got {self.sort_tiebreak!r}", "sort_tiebreak"
            )
        for name in ("h", "g"):
            curve = getattr(self, name)
            if not callable(curve) and (not curve or not all(isinstance(a, int | float) for a in curve)):
                raise InputError(f"{name} must be a callable or a list of polynomial coefficients", name)

    def to_dict(self) -> dict[str, Any]:
        def curve(c: Curve) -> Any:
            return getattr(c, "__name__", "callable") if callable(c) else list(c)

        return {"k": self.k, "h": curve(self.h), "g": curve(self.g), "b_score_argument": self.b_score_argument,
                "sort_tiebreak": self.sort_tiebreak, "check_resources": self.check_resources}  # fmt: skip


# ---- the ledger of reservations (bind phase) ---------------------------------------------------------------
@dataclass
class Binding:
    container: str
    node: str
    utilization: float
    cpu: float
    memory_mib: float
    criticality: str


@dataclass
class Ledger:
    """What is reserved on each node: RT utilization (sum of WCET/P), CPU and memory requests.

    Per-node sums are kept up to date on every bind and release (with ``math.fsum`` over the node's
    bindings, so that eight reservations of 0.95 add up to exactly 7.6), which makes the filters O(1).
    """

    nodes: list[str]
    bindings: dict[str, Binding] = field(default_factory=dict)
    _sums: dict[str, tuple[float, float, float]] = field(default_factory=dict, init=False, repr=False, compare=False)
    _members: dict[str, dict[str, Binding]] = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for b in self.bindings.values():
            self._members.setdefault(b.node, {})[b.container] = b
        for node in self._members:
            self._recompute(node)

    @classmethod
    def for_nodes(cls, nodes: Iterable[RTNode]) -> Ledger:
        return cls([n.name for n in nodes])

    def _recompute(self, node: str) -> None:
        members = self._members.get(node, {}).values()
        self._sums[node] = (
            math.fsum(b.utilization for b in members),
            math.fsum(b.cpu for b in members),
            math.fsum(b.memory_mib for b in members),
        )

    def current_ut(self, node: str) -> float:
        return self._sums.get(node, (0.0, 0.0, 0.0))[0]

    def cpu_used(self, node: str) -> float:
        return self._sums.get(node, (0.0, 0.0, 0.0))[1]

    def memory_used(self, node: str) -> float:
        return self._sums.get(node, (0.0, 0.0, 0.0))[2]

    def on_node(self, node: str) -> list[Binding]:
        return list(self._members.get(node, {}).values())

    def where(self, container: str) -> str | None:
        b = self.bindings.get(container)
        return b.node if b else None

    @classmethod
    def with_reservations(cls, nodes: Iterable[RTNode], placed: Iterable[tuple[RTContainer, str]]) -> Ledger:
        """A ledger holding every ``(container, node)`` reservation, as ``reserve`` one by one would, with each
        node's sums computed once (``reserve`` recomputes its node's: quadratic in the pods of a node)."""
        bindings: dict[str, Binding] = {}
        for container, node in placed:
            if container.name in bindings:
                raise InputError(f"container {container.name!r} is already bound to {bindings[container.name].node}")
            bindings[container.name] = cls._binding(container, node)
        return cls([n.name for n in nodes], bindings)

    @staticmethod
    def _binding(container: RTContainer, node: str) -> Binding:
        util = container.utilization(node)
        if util is None:
            # Only an RT-unaware scheduler binds here; the task would run with its largest declared runtime.
            util = container.max_utilization()
        return Binding(container.name, node, util, container.cpu, container.memory_mib, container.criticality)

    def reserve(self, container: RTContainer, node: str) -> Binding:
        if container.name in self.bindings:
            raise InputError(f"container {container.name!r} is already bound to {self.bindings[container.name].node}")
        b = self._binding(container, node)
        self.bindings[container.name] = b
        self._members.setdefault(node, {})[container.name] = b
        self._recompute(node)
        return b

    def release(self, container: str) -> Binding | None:
        b = self.bindings.pop(container, None)
        if b is not None:
            del self._members[b.node][container]
            self._recompute(b.node)
        return b

    def utilization(self) -> dict[str, float]:
        return {n: self.current_ut(n) for n in self.nodes}

    def copy(self) -> Ledger:
        return Ledger(list(self.nodes), dict(self.bindings))


# ---- Eq. 3.17 / 3.18 / Algorithm 4 ---------------------------------------------------------------------------
def n_rank(threshold: float, new_ut: float) -> float:
    """Normalized free RT capacity after placement, ``(thresholdUT - newUT) / thresholdUT`` (Alg. 4, line 2)."""
    return (threshold - new_ut) / threshold


def _apply(curve: Curve, z: float) -> float:
    if callable(curve):
        return float(curve(z))
    value = 0.0
    for coeff in curve:  # Horner
        value = value * z + coeff
    return value


def b_curve(z: float, params: RTKubeParams | None = None) -> float:
    """Eq. 3.18: ``h(z)`` when ``z <= 1/K``, else ``g(z)``."""
    p = params or RTKubeParams()
    return _apply(p.h, z) if z <= 1 / p.k else _apply(p.g, z)


def rt_score(criticality: str, threshold: float, new_ut: float, params: RTKubeParams | None = None) -> float:
    """Algorithm 4: the score of an RT container of ``criticality`` on a node after placement."""
    p = params or RTKubeParams()
    rank = n_rank(threshold, new_ut)
    if criticality == "A":
        return 1 - rank
    if criticality == "B":
        return b_curve(rank if p.b_score_argument == "free" else 1 - rank, p)
    if criticality == "C":
        return rank
    raise InputError(f"criticality {criticality!r} has no RT score", "criticality")


def kube_score(score: float) -> int:
    """The value a kube-scheduler Score plugin returns (``MaxNodeScore = 100``)."""
    return round(100 * score)


def least_allocated(container: RTContainer, node: RTNode, ledger: Ledger) -> float:
    """Kubernetes' default NodeResourcesFit score (LeastAllocated), on a 0-1 scale, over CPU and memory."""
    parts = []
    if node.cpu > 0:
        parts.append((node.cpu - ledger.cpu_used(node.name) - container.cpu) / node.cpu)
    if 0 < node.memory_mib < math.inf:
        parts.append((node.memory_mib - ledger.memory_used(node.name) - container.memory_mib) / node.memory_mib)
    return max(0.0, sum(parts) / len(parts)) if parts else 1.0


# ---- filters ------------------------------------------------------------------------------------------------------
@functools.lru_cache(maxsize=4096)
def _first_untolerated(taints: tuple[Taint, ...], tolerations: tuple[Toleration, ...], now: float | None) -> str | None:
    bad = untolerated(taints, tolerations, now)
    return str(bad[0]) if bad else None


def _taint_filter(c: RTContainer, n: RTNode, ledger: Ledger, now: float | None) -> str | None:
    if not n.taints:
        return None
    # Only timed taints depend on the time; leaving it out of the cache key otherwise keeps the cache small.
    timed = any(t.until is not None for t in n.taints)
    bad = _first_untolerated(n.taints, c.tolerations, now if timed else None)
    return f"untolerated taint {bad}" if bad else None


def _resource_filter(c: RTContainer, n: RTNode, ledger: Ledger, now: float | None) -> str | None:
    used = ledger.cpu_used(n.name)
    if c.cpu and used + c.cpu > n.cpu + ADMISSION_EPS:
        return f"insufficient cpu: {c.cpu:g} requested, {n.cpu - used:g} of {n.cpu:g} free"
    mem = ledger.memory_used(n.name)
    if c.memory_mib and mem + c.memory_mib > n.memory_mib:
        return f"insufficient memory: {c.memory_mib:g} MiB requested, {n.memory_mib - mem:g} MiB free"
    return None


@dataclass(frozen=True)
class Filtered:
    """The outcome of the filters for one node: the failing filter or the projected RT utilization."""

    rejected_by: str | None
    reason: str
    current_ut: float = 0.0
    new_ut: float | None = None


def rt_filter(
    container: RTContainer, node: RTNode, ledger: Ledger, now: float | None = None, check_resources: bool = True
) -> Filtered:
    """Every filter RT-Kube runs for one node, in order; Algorithm 3 for RT containers."""
    reason = _taint_filter(container, node, ledger, now)
    if reason:
        return Filtered("TaintToleration", reason)
    if check_resources:
        reason = _resource_filter(container, node, ledger, now)
        if reason:
            return Filtered("NodeResourcesFit", reason)
    if not container.is_rt:
        return Filtered(None, "")
    if not node.rt:
        return Filtered("RealTimeNode", "node has no real-time kernel")
    current = ledger.current_ut(node.name)
    util = container.utilization(node.name)
    if util is None:
        return Filtered("RealTimeWcet", "no WCET given for this node", current)
    new_ut = current + util
    # Algorithm 3, line 6 (Eq. 2.4): only a strict excess fails.
    if new_ut > node.rt_threshold * (1 + ADMISSION_EPS):
        return Filtered(
            "RealTimeAdmission",
            f"projected RT utilization {new_ut:.4f} > threshold {node.rt_threshold:.4f}",
            current,
            new_ut,
        )
    # Algorithm 3, line 8: criticality separation.
    if (container.criticality == "C") != node.is_c_node:
        what = "non-C" if container.criticality != "C" else "C"
        where = "C" if node.is_c_node else "non-C"
        return Filtered("RealTimeCriticality", f"{what} container on a {where} node", current, new_ut)
    return Filtered(None, "", current, new_ut)


# ---- sort ----------------------------------------------------------------------------------------------------------
def sort_queue(containers: Iterable[RTContainer], tiebreak: str = "arrival") -> list[RTContainer]:
    """Criticality first (C, B, A, NONE); then creation (or utilization, highest first), then name."""
    if tiebreak == "utilization":
        return sorted(containers, key=lambda c: (-c.rank, -c.max_utilization(), c.arrival, c.name))
    return sorted(containers, key=lambda c: (-c.rank, c.arrival, c.name))


# ---- one container -------------------------------------------------------------------------------------------------
def node_verdict(
    container: RTContainer, node: RTNode, ledger: Ledger, params: RTKubeParams | None = None, now: float | None = None
) -> NodeVerdict:
    """One node's verdict for one container: the filter that rejects it, or its score and why ("why not X?")."""
    p = params or RTKubeParams()
    f = rt_filter(container, node, ledger, now, p.check_resources)
    if f.rejected_by:
        return NodeVerdict(node.name, f.rejected_by, f.reason)
    if container.is_rt:
        assert f.new_ut is not None
        s = rt_score(container.criticality, node.rt_threshold, f.new_ut, p)
        policy = f"realtime_{container.criticality}"
        why = (
            f"currentUT {f.current_ut:.4f}, newUT {f.new_ut:.4f} of {node.rt_threshold:.4f}, "
            f"nRank {n_rank(node.rt_threshold, f.new_ut):.4f}"
        )
    else:
        s = least_allocated(container, node, ledger)
        policy, why = "least_allocated", "standard container: default Kubernetes score"
    return NodeVerdict(node.name, None, why, {policy: s}, s)


def place_one(
    container: RTContainer,
    nodes: Sequence[RTNode],
    ledger: Ledger,
    params: RTKubeParams | None = None,
    now: float | None = None,
) -> Decision:
    """Filter, score and choose a node for one container; the ledger is not changed (bind does that)."""
    p = params or RTKubeParams()
    verdicts = []
    best: tuple[float, str] | None = None
    for node in sorted(nodes, key=lambda n: n.name):
        v = node_verdict(container, node, ledger, p, now)
        verdicts.append(v)
        if v.rejected_by or v.total is None:
            continue
        s = v.total
        # Highest score wins; nodes are visited by name, so a tie keeps the lowest name.
        if best is None or s > best[0] + 1e-12:
            best = (s, node.name)
    if best is None:
        return Decision(container.name, None, None, tuple(verdicts))
    return Decision(container.name, best[1], best[0], tuple(verdicts))


def schedule(
    containers: Iterable[RTContainer],
    nodes: Sequence[RTNode],
    params: RTKubeParams | None = None,
    ledger: Ledger | None = None,
    now: float | None = None,
) -> PlacementPlan:
    """One scheduler pass: sort, then filter/score/bind each container in queue order.

    ``ledger`` holds what is already bound (it is updated in place with the new bindings); ``now`` makes
    timed taints expire. The plan's ``utilization`` metric is each node's ``currentUT`` after the pass.
    """
    p = params or RTKubeParams()
    _check_nodes(nodes)
    book = ledger if ledger is not None else Ledger.for_nodes(nodes)
    for n in nodes:
        if n.name not in book.nodes:
            book.nodes.append(n.name)
    queue = sort_queue(containers, p.sort_tiebreak)
    decisions = []
    for c in queue:
        d = place_one(c, nodes, book, p, now)
        if d.node is not None:
            book.reserve(c, d.node)
        decisions.append(d)
    return PlacementPlan(
        "rt_kube",
        decisions,
        params=p.to_dict(),
        metrics={"utilization": book.utilization(), "thresholds": {n.name: n.rt_threshold for n in nodes}},
    )


def kube_default(
    containers: Iterable[RTContainer],
    nodes: Sequence[RTNode],
    ledger: Ledger | None = None,
    rng: random.Random | None = None,
    pin: str | None = None,
    now: float | None = None,
) -> PlacementPlan:
    """The RT-unaware default scheduler: creation order, taints + requests, LeastAllocated, random ties.

    ``pin`` restricts every container to one node (a ``nodeSelector``), which is how the thesis' "K3S
    standard" run ended with every container on the Jetson (Table 4.31).
    """
    _check_nodes(nodes)
    if pin is not None and pin not in {n.name for n in nodes}:
        raise InputError(f"pinned node {pin!r} is not in the cluster", "pin")
    r = rng or random.Random(0)
    book = ledger if ledger is not None else Ledger.for_nodes(nodes)
    decisions = []
    for c in sorted(containers, key=lambda c: (c.arrival, c.name)):
        verdicts, scored = [], []
        for node in sorted(nodes, key=lambda n: n.name):
            if pin is not None and node.name != pin:
                verdicts.append(NodeVerdict(node.name, "NodeAffinity", f"node selector requires {pin}"))
                continue
            reason = _taint_filter(c, node, book, now)
            rejected = "TaintToleration" if reason else None
            if not reason:
                reason = _resource_filter(c, node, book, now)
                rejected = "NodeResourcesFit" if reason else None
            if rejected:
                verdicts.append(NodeVerdict(node.name, rejected, reason or ""))
                continue
            s = least_allocated(c, node, book)
            verdicts.append(NodeVerdict(node.name, None, "", {"least_allocated": s}, s))
            scored.append((s, node.name))
        if not scored:
            decisions.append(Decision(c.name, None, None, tuple(verdicts)))
            continue
        top = max(s for s, _ in scored)
        choice = r.choice([name for s, name in scored if s >= top - 1e-12])
        book.reserve(c, choice)
        decisions.append(Decision(c.name, choice, top, tuple(verdicts)))
    return PlacementPlan(
        "k8s_default",
        decisions,
        params={"pin": pin},
        metrics={"utilization": book.utilization(), "thresholds": {n.name: n.rt_threshold for n in nodes}},
    )


def _check_nodes(nodes: Sequence[RTNode]) -> None:
    if not nodes:
        raise InputError("the cluster has no nodes", "nodes")


def explain(plan: PlacementPlan) -> list[dict[str, Any]]:
    """The dry-run table (spec 03, 16.3): one row per container and node with the filter or the score."""
    rows = []
    for d in plan.decisions:
        for v in d.verdicts:
            rows.append(
                {
                    "container": d.item,
                    "node": v.node,
                    "chosen": v.node == d.node,
                    "rejected_by": v.rejected_by,
                    "reason": v.reason,
                    "score": v.total,
                }
            )
    return rows


def placements_by_node(plan: PlacementPlan) -> Mapping[str, list[str]]:
    out: dict[str, list[str]] = {}
    for d in plan.decisions:
        if d.node is not None:
            out.setdefault(d.node, []).append(d.item)
    return out
