"""RT-Kube's scheduler vectorised over nodes (thesis 3.4, Fig. 3.34, Algorithms 3-4, Eqs. 2.4, 3.17-3.18).

The same four phases and the same choices as :mod:`continuum.engine.rtkube.rt_kube` (the reference, kept
as it is and checked against this module on random instances, ties included), with each container's
filters and scores computed for every node at once with numpy:

* a **node-feature matrix** (columns: RT kernel, C node, CPU, memory, ``thresholdUT`` and the reserved RT
  utilization, CPU and memory) built once per pass, with nodes in name order (the reference's visiting
  order), and updated incrementally: binding a container rewrites only its node's reserved sums, read from
  the :class:`~continuum.engine.rtkube.rt_kube.Ledger` (``math.fsum`` of the node's bindings, so the values
  are bit-identical to the reference's);
* the **taint filter** per distinct taint set rather than per node (a cluster has a handful: none, the
  ``RealTime`` taint, a monitor's timed taint...), cached per toleration set for the pass;
* **Algorithm 3** (``newUT = currentUT + WCET(n)/P <= thresholdUT`` with the reference's relative slack,
  the XOR criticality rule) and **Algorithm 4 / Eq. 3.18** (``nRank``, the A/B/C scores, Horner's rule for
  h and g) as array expressions doing the reference's floating-point operations in the reference's order;
* the **choice** as the reference's scan ("highest score, a later node must beat the best by 1e-12") done
  exactly without a Python loop: only nodes that raise the running maximum can become the best, and only
  those raising it by at most 1e-12 need the scalar comparison (in practice none).

The explanation no longer costs the decision: each :class:`~continuum.engine.core.placement.Decision` keeps
the top ``top_k`` candidates with their scores, up to ``top_k`` example nodes per rejecting filter, and the
count of nodes each filter rejected (``Decision.rejections``), so its size does not grow with the cluster.
A node's full verdict ("why not node X?") is :func:`why_not`, from the same filters
(:func:`continuum.engine.rtkube.rt_kube.node_verdict`); ``full="pending"`` or ``"all"`` keeps every node's
verdict (as the reference does) for the pending containers or for all.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from continuum.engine.core.placement import Decision, NodeVerdict, PlacementPlan
from continuum.engine.rtkube import rt_kube
from continuum.engine.rtkube.rt_kube import ADMISSION_EPS, Ledger, RTKubeParams
from continuum.engine.rtkube.rt_model import RTContainer, RTNode

__all__ = ["EXAMPLES", "FILTERS", "TOP_K", "NodeMatrix", "bound_decision", "place_one", "schedule", "why_not"]

#: The filters in the reference's order (``rt_kube.rt_filter``); index 0 means "passed".
FILTERS = (
    "",
    "TaintToleration",
    "NodeResourcesFit",
    "RealTimeNode",
    "RealTimeWcet",
    "RealTimeAdmission",
    "RealTimeCriticality",
)
#: Candidates a decision keeps by default, and example nodes per rejecting filter.
TOP_K = 5
EXAMPLES = 3
_TIE = 1e-12  # the reference's tie margin


class NodeMatrix:
    """The nodes of one pass as columns of arrays, in name order, with the ledger's reservations."""

    def __init__(self, nodes: Sequence[RTNode], ledger: Ledger) -> None:
        self.nodes = sorted(nodes, key=lambda n: n.name)
        self.names = [n.name for n in self.nodes]
        self.pos = {name: i for i, name in enumerate(self.names)}
        self.ledger = ledger
        self.rt = np.array([n.rt for n in self.nodes], dtype=bool)
        self.c_node = np.array([n.is_c_node for n in self.nodes], dtype=bool)
        self.cpu = np.array([n.cpu for n in self.nodes], dtype=float)
        self.mem = np.array([n.memory_mib for n in self.nodes], dtype=float)
        self.threshold = np.array([n.rt_threshold for n in self.nodes], dtype=float)
        self.admit = self.threshold * (1 + ADMISSION_EPS)  # Algorithm 3, line 6, as the reference computes it
        # LeastAllocated's terms (rt_kube.least_allocated): which resources count, per node.
        self.has_cpu = self.cpu > 0
        self.has_mem = (self.mem > 0) & (self.mem < math.inf)
        self.n_parts = self.has_cpu.astype(float) + self.has_mem
        self.ut = np.array([ledger.current_ut(n) for n in self.names], dtype=float)
        self.cpu_used = np.array([ledger.cpu_used(n) for n in self.names], dtype=float)
        self.mem_used = np.array([ledger.memory_used(n) for n in self.names], dtype=float)
        # Distinct taint sets: the taint filter runs once per set and container tolerations.
        groups: dict[tuple, int] = {}
        self.taint_group = np.array([groups.setdefault(n.taints, len(groups)) for n in self.nodes], dtype=np.intp)
        self.taint_sets = list(groups)
        self._tolerated: dict[tuple, np.ndarray] = {}

    def __len__(self) -> int:
        return len(self.names)

    def refresh(self, node: str) -> None:
        """Read one node's reserved sums back from the ledger after a bind or a release."""
        i = self.pos[node]
        self.ut[i] = self.ledger.current_ut(node)
        self.cpu_used[i] = self.ledger.cpu_used(node)
        self.mem_used[i] = self.ledger.memory_used(node)

    def taint_ok(self, container: RTContainer, now: float | None) -> np.ndarray:
        key = container.tolerations
        ok = self._tolerated.get(key)
        if ok is None:
            per_set = np.empty(len(self.taint_sets), dtype=bool)
            for g, taints in enumerate(self.taint_sets):
                if not taints:
                    per_set[g] = True
                    continue
                timed = any(t.until is not None for t in taints)
                per_set[g] = rt_kube._first_untolerated(taints, key, now if timed else None) is None
            ok = per_set[self.taint_group]
            self._tolerated[key] = ok
        return ok

    def utilization(self, container: RTContainer) -> np.ndarray:
        """``WCET(n) / P`` per node (Eq. 2.4's term), NaN where the container has no WCET for the node."""
        util = np.full(len(self.names), np.nan)
        if container.period is None or not container.wcet:
            return util
        try:
            idx = np.fromiter(map(self.pos.__getitem__, container.wcet), np.intp, len(container.wcet))
            vals = np.fromiter(container.wcet.values(), float, len(container.wcet))
        except KeyError:  # a WCET for a node outside the pass: ignored, as the reference never asks for it
            known = [(self.pos[k], v) for k, v in container.wcet.items() if k in self.pos]
            idx = np.array([i for i, _ in known], dtype=np.intp)
            vals = np.array([v for _, v in known], dtype=float)
        util[idx] = vals / container.period
        return util


def _horner(curve: Any, z: np.ndarray) -> np.ndarray:
    if callable(curve):
        return np.array([float(curve(x)) for x in z.tolist()], dtype=float)
    value = np.zeros_like(z)
    for coeff in curve:  # the reference's Horner loop, elementwise (no fused multiply-add)
        value = value * z + coeff
    return value


def _evaluate(c: RTContainer, m: NodeMatrix, p: RTKubeParams, now: float | None) -> tuple[np.ndarray, np.ndarray]:
    """(filter code per node, score per node with -inf where a filter rejects the node)."""
    n = len(m)
    code = np.zeros(n, dtype=np.int8)
    score = np.full(n, -np.inf)
    if c.is_rt:
        util = m.utilization(c)
        new_ut = m.ut + util
        with np.errstate(invalid="ignore"):
            code[(c.criticality == "C") != m.c_node] = 6  # Algorithm 3, line 8 (XOR)
            code[new_ut > m.admit] = 5  # Algorithm 3, line 6 (Eq. 2.4)
        code[np.isnan(util)] = 4
        code[~m.rt] = 3
    if p.check_resources:
        if c.memory_mib:
            code[m.mem_used + c.memory_mib > m.mem] = 2
        if c.cpu:
            code[m.cpu_used + c.cpu > m.cpu + ADMISSION_EPS] = 2
    code[~m.taint_ok(c, now)] = 1
    ok = code == 0
    if not ok.any():
        return code, score
    if c.is_rt:
        thr = m.threshold[ok]
        rank = (thr - new_ut[ok]) / thr  # Alg. 4, line 2
        if c.criticality == "A":
            s = 1 - rank
        elif c.criticality == "C":
            s = rank
        else:  # B: Eq. 3.18
            z = rank if p.b_score_argument == "free" else 1 - rank
            low = z <= 1 / p.k
            s = np.empty_like(z)
            if low.any():
                s[low] = _horner(p.h, z[low])
            if (~low).any():
                s[~low] = _horner(p.g, z[~low])
    else:  # LeastAllocated (rt_kube.least_allocated)
        cpu, mem = m.cpu[ok], m.mem[ok]
        with np.errstate(invalid="ignore", divide="ignore"):
            part_cpu = (cpu - m.cpu_used[ok] - c.cpu) / cpu
            part_mem = (mem - m.mem_used[ok] - c.memory_mib) / mem
        total = np.where(m.has_cpu[ok], part_cpu, 0.0) + np.where(m.has_mem[ok], part_mem, 0.0)
        parts = m.n_parts[ok]
        with np.errstate(invalid="ignore", divide="ignore"):
            s = np.where(parts > 0, np.maximum(0.0, total / parts), 1.0)
    score[ok] = s
    return code, score


def _choose(score: np.ndarray) -> int | None:
    """The reference's scan, exactly: visiting in order, a node becomes the best when it beats the best
    so far by more than 1e-12. Only a node above the running maximum can; one above it by more than 1e-12
    surely does (the best is at most the maximum), so the scan starts at the last such node."""
    if not np.isfinite(score).any():
        return None
    prev = np.empty_like(score)
    prev[0] = -np.inf
    np.maximum.accumulate(score[:-1], out=prev[1:])
    sure = np.flatnonzero(score > prev + _TIE)
    best = int(sure[-1])
    state = float(score[best])
    for i in np.flatnonzero((score > prev) & (score <= prev + _TIE)).tolist():
        if i > best and score[i] > state + _TIE:
            best, state = i, float(score[i])
    return best


def _top(score: np.ndarray, k: int) -> list[int]:
    """The ``k`` best nodes by score, ties by name (index)."""
    feasible = int(np.isfinite(score).sum())
    if feasible == 0 or k <= 0:
        return []
    if feasible <= k:
        idx = np.flatnonzero(np.isfinite(score))
    else:
        kth = np.partition(score, -k)[-k]
        above = np.flatnonzero(score > kth)
        ties = np.flatnonzero(score == kth)[: k - len(above)]
        idx = np.concatenate([above, ties])
    order = np.lexsort((idx, -score[idx]))
    return idx[order][:k].tolist()


def place_one(
    c: RTContainer,
    m: NodeMatrix,
    params: RTKubeParams | None = None,
    now: float | None = None,
    top_k: int = TOP_K,
    full: bool = False,
    examples: int = EXAMPLES,
) -> Decision:
    """Filter, score and choose a node for one container (the ledger is not changed; bind does that)."""
    p = params or RTKubeParams()
    code, score = _evaluate(c, m, p, now)
    best = _choose(score)

    def verdict(i: int) -> NodeVerdict:
        return rt_kube.node_verdict(c, m.nodes[i], m.ledger, p, now)

    if full:
        verdicts = tuple(verdict(i) for i in range(len(m)))
        rejections: dict[str, int] = {}
    else:
        shown = _top(score, top_k)
        if best is not None and best not in shown:
            shown = [best, *shown[: top_k - 1]]
        counts = np.bincount(code, minlength=len(FILTERS))
        rejections = {FILTERS[f]: int(counts[f]) for f in range(1, len(FILTERS)) if counts[f]}
        for f in rejections:
            shown += np.flatnonzero(code == FILTERS.index(f))[:examples].tolist()
        verdicts = tuple(verdict(i) for i in shown)
    if best is None:
        return Decision(c.name, None, None, verdicts, rejections)
    return Decision(c.name, m.names[best], float(score[best]), verdicts, rejections)


def schedule(
    containers: Iterable[RTContainer],
    nodes: Sequence[RTNode],
    params: RTKubeParams | None = None,
    ledger: Ledger | None = None,
    now: float | None = None,
    top_k: int = TOP_K,
    full: str = "none",
    examples: int = EXAMPLES,
) -> PlacementPlan:
    """One scheduler pass (``rt_kube.schedule``'s contract and choices): sort, then filter/score/bind each
    container in queue order. ``full``: ``"none"`` (bounded explanations), ``"pending"`` (every node's
    verdict for the containers left pending) or ``"all"`` (every node's verdict, as the reference)."""
    if full not in ("none", "pending", "all"):
        raise ValueError(f"full must be none, pending or all, got {full!r}")
    p = params or RTKubeParams()
    rt_kube._check_nodes(nodes)
    book = ledger if ledger is not None else Ledger.for_nodes(nodes)
    known = set(book.nodes)
    for n in nodes:
        if n.name not in known:
            book.nodes.append(n.name)
    matrix = NodeMatrix(nodes, book)
    decisions = []
    for c in rt_kube.sort_queue(containers, p.sort_tiebreak):
        d = place_one(c, matrix, p, now, top_k, full == "all", examples)
        if d.node is not None:
            book.reserve(c, d.node)
            matrix.refresh(d.node)
        elif full == "pending":
            d = place_one(c, matrix, p, now, top_k, True)
        decisions.append(d)
    return PlacementPlan(
        "rt_kube",
        decisions,
        params=p.to_dict(),
        metrics={"utilization": book.utilization(), "thresholds": {n.name: n.rt_threshold for n in nodes}},
    )


def why_not(
    container: RTContainer,
    nodes: Sequence[RTNode],
    ledger: Ledger,
    params: RTKubeParams | None = None,
    now: float | None = None,
    node: str | None = None,
) -> list[NodeVerdict]:
    """The full explanation on demand: every node's verdict for ``container`` against ``ledger`` (in name
    order), or only ``node``'s -- the reference's filters and scores (``rt_kube.node_verdict``)."""
    p = params or RTKubeParams()
    chosen = [n for n in nodes if node is None or n.name == node]
    return [rt_kube.node_verdict(container, n, ledger, p, now) for n in sorted(chosen, key=lambda n: n.name)]


def bound_decision(doc: dict[str, Any], top_k: int = TOP_K, examples: int = EXAMPLES) -> dict[str, Any]:
    """A stored ``Decision.to_dict()`` with every node's verdict cut to the bounded form :func:`place_one`
    keeps: the ``top_k`` best scored nodes (the chosen one first), ``examples`` nodes per rejecting filter
    and the count per filter (``rejections``). A document bounded already is returned unchanged."""
    verdicts = doc.get("verdicts") or []
    if "rejections" in doc or len(verdicts) <= top_k:
        return doc
    scored = [v for v in verdicts if not v.get("rejected_by")]
    scored.sort(key=lambda v: -(v.get("total") if v.get("total") is not None else -math.inf))
    top = scored[:top_k]
    chosen = [v for v in scored if v.get("node") == doc.get("node")]
    if chosen and chosen[0] not in top:
        top = [chosen[0], *top[: top_k - 1]]
    counts: dict[str, int] = {}
    shown: list[dict] = []
    for v in verdicts:
        f = v.get("rejected_by")
        if f:
            counts[f] = counts.get(f, 0) + 1
            if counts[f] <= examples:
                shown.append(v)
    return {**doc, "verdicts": top + shown, "rejections": counts}
