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

__all__ = [
    "EXAMPLES",
    "FILTERS",
    "FULL_UP_TO",
    "TOP_K",
    "NodeMatrix",
    "bound_decision",
    "place_one",
    "schedule",
    "why_not",
]

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
EXAMPLES = 1
#: With ``full="auto"``, a cluster of at most this many nodes keeps every node's verdict (bounded anyway).
FULL_UP_TO = 32
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
        self.cpu_cap = self.cpu + ADMISSION_EPS  # the reference's ``n.cpu + ADMISSION_EPS``
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
        self._tolerated: dict[tuple, tuple[np.ndarray, int]] = {}
        self._wcet_index: dict[tuple, np.ndarray] = {}

    def __len__(self) -> int:
        return len(self.names)

    def refresh(self, node: str) -> None:
        """Read one node's reserved sums back from the ledger after a bind or a release."""
        i = self.pos[node]
        self.ut[i] = self.ledger.current_ut(node)
        self.cpu_used[i] = self.ledger.cpu_used(node)
        self.mem_used[i] = self.ledger.memory_used(node)

    def taint_ok(self, container: RTContainer, now: float | None) -> tuple[np.ndarray, int]:
        """(nodes whose taints the container tolerates, how many), cached per toleration set for the pass."""
        key = container.tolerations
        hit = self._tolerated.get(key)
        if hit is None:
            per_set = np.empty(len(self.taint_sets), dtype=bool)
            for g, taints in enumerate(self.taint_sets):
                if not taints:
                    per_set[g] = True
                    continue
                timed = any(t.until is not None for t in taints)
                per_set[g] = rt_kube._first_untolerated(taints, key, now if timed else None) is None
            ok = per_set[self.taint_group]
            hit = self._tolerated[key] = (ok, int(np.count_nonzero(ok)))
        return hit

    def utilization(self, container: RTContainer) -> np.ndarray:
        """``WCET(n) / P`` per node (Eq. 2.4's term), NaN where the container has no WCET for the node."""
        util = np.full(len(self.names), np.nan)
        wcet = container.wcet
        if container.period is None or not wcet:
            return util
        # Containers of one application list the same nodes: their positions are looked up once.
        keys = tuple(wcet)
        idx = self._wcet_index.get(keys)
        if idx is None:
            idx = np.array([self.pos.get(k, -1) for k in keys], dtype=np.intp)
            self._wcet_index[keys] = idx
        vals = np.fromiter(wcet.values(), float, len(keys))
        if idx.size and idx.min() < 0:  # a WCET for a node outside the pass: ignored, as by the reference
            vals, idx = vals[idx >= 0], idx[idx >= 0]
        util[idx] = vals / container.period
        return util


def _horner(curve: Any, z: np.ndarray) -> np.ndarray:
    if callable(curve):
        return np.array([float(curve(x)) for x in z.tolist()], dtype=float)
    value = np.zeros_like(z)
    for coeff in curve:  # the reference's Horner loop, elementwise (no fused multiply-add)
        value = value * z + coeff
    return value


def _b_scores(p: RTKubeParams, z: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """Eq. 3.18 (``h(z)`` when ``z <= 1/K``, else ``g(z)``): polynomials over every node, callables only on
    the nodes that passed the filters (a callable is the caller's code: it sees only real arguments)."""
    low = z <= 1 / p.k
    if not callable(p.h) and not callable(p.g):
        return np.where(low, _horner(p.h, z), _horner(p.g, z))
    s = np.full_like(z, -np.inf)
    for mask, curve in ((ok & low, p.h), (ok & ~low, p.g)):
        if mask.any():
            s[mask] = _horner(curve, z[mask])
    return s


class _Eval:
    """One container against every node: the nodes left after each filter, in the reference's order, and
    the score of the nodes left after all of them (-inf elsewhere)."""

    __slots__ = ("left", "new_ut", "score")

    def __init__(self, c: RTContainer, m: NodeMatrix, p: RTKubeParams, now: float | None) -> None:
        taint_ok, _ = m.taint_ok(c, now)
        #: (filter index, nodes still in after it), for the filters that ran; the last one is "passed all".
        left: list[tuple[int, np.ndarray]] = [(1, taint_ok)]
        ok = taint_ok
        if p.check_resources and (c.cpu or c.memory_mib):
            fit = ok
            if c.cpu:
                fit = fit & (m.cpu_used + c.cpu <= m.cpu_cap)
            if c.memory_mib:
                fit = fit & (m.mem_used + c.memory_mib <= m.mem)
            ok = fit
            left.append((2, ok))
        self.new_ut = None
        if c.is_rt:
            ok = ok & m.rt
            left.append((3, ok))
            new_ut = m.ut + m.utilization(c)
            ok = ok & (new_ut == new_ut)  # NaN: no WCET for the node
            left.append((4, ok))
            ok = ok & (new_ut <= m.admit)  # Algorithm 3, line 6 (Eq. 2.4): only a strict excess fails
            left.append((5, ok))
            ok = ok & (m.c_node if c.criticality == "C" else ~m.c_node)  # Algorithm 3, line 8 (XOR)
            left.append((6, ok))
            self.new_ut = new_ut
        self.left = left
        if not ok.any():
            self.score = np.full(len(m), -np.inf)
            return
        # Scores over every node (no boolean indexing, the costly part), kept where the filters passed.
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            if c.is_rt:
                rank = (m.threshold - new_ut) / m.threshold  # Alg. 4, line 2
                if c.criticality == "A":
                    s = 1 - rank
                elif c.criticality == "C":
                    s = rank
                else:  # B: Eq. 3.18
                    z = rank if p.b_score_argument == "free" else 1 - rank
                    s = _b_scores(p, z, ok)
            else:  # LeastAllocated (rt_kube.least_allocated)
                part_cpu = (m.cpu - m.cpu_used - c.cpu) / m.cpu
                part_mem = (m.mem - m.mem_used - c.memory_mib) / m.mem
                total = np.where(m.has_cpu, part_cpu, 0.0) + np.where(m.has_mem, part_mem, 0.0)
                s = np.where(m.n_parts > 0, np.maximum(0.0, total / m.n_parts), 1.0)
        self.score = np.where(ok, s, -np.inf)

    def rejected(self, n: int) -> list[tuple[int, int, np.ndarray | None, np.ndarray]]:
        """(filter index, nodes it rejected, mask before it (None: every node), mask after it) for each filter
        that rejected some."""
        out: list[tuple[int, int, np.ndarray | None, np.ndarray]] = []
        before: np.ndarray | None = None
        before_count = n
        for f, mask in self.left:
            count = int(np.count_nonzero(mask))
            if count < before_count:
                out.append((f, before_count - count, before, mask))
            before, before_count = mask, count
        return out


def _choose(score: np.ndarray) -> int | None:
    """The reference's scan, exactly: visiting in order, a node becomes the best when it beats the best
    so far by more than 1e-12. Usually the first maximum is the answer (nothing before it is within 1e-12
    of it); otherwise only a node above the running maximum can become the best, one above it by more
    than 1e-12 surely does (the best is at most the maximum), so the scan starts at the last such node."""
    first = int(np.argmax(score))
    top = score[first]
    if top == -np.inf:
        return None
    if first == 0 or score[:first].max() + _TIE < top:
        return first
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
    """The ``k`` best nodes by score, ties by name (index): ``argmax`` returns the first maximum."""
    out: list[int] = []
    work = None
    for _ in range(k):
        i = int(np.argmax(score if work is None else work))
        if (score if work is None else work)[i] == -np.inf:
            break
        out.append(i)
        if work is None:
            work = score.copy()
        work[i] = -np.inf
    return out


def _scored_verdict(c: RTContainer, m: NodeMatrix, e: _Eval, i: int) -> NodeVerdict:
    """``rt_kube.node_verdict`` of a node that passed the filters, from the arrays (same values, same text)."""
    s = float(e.score[i])
    if not c.is_rt:
        return NodeVerdict(m.names[i], None, "standard container: default Kubernetes score", {"least_allocated": s}, s)
    assert e.new_ut is not None
    cur, new, thr = float(m.ut[i]), float(e.new_ut[i]), float(m.threshold[i])
    why = f"currentUT {cur:.4f}, newUT {new:.4f} of {thr:.4f}, nRank {rt_kube.n_rank(thr, new):.4f}"
    return NodeVerdict(m.names[i], None, why, {f"realtime_{c.criticality}": s}, s)


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
    e = _Eval(c, m, p, now)
    best = _choose(e.score)
    if full:
        # A node that passed the filters: its verdict from the arrays (the reference's values and text, as the
        # bounded form keeps them); a rejected one: the reference's filters say which rejects it and why.
        passed = e.left[-1][1].tolist()
        verdicts = tuple(
            _scored_verdict(c, m, e, i) if ok else rt_kube.node_verdict(c, node, m.ledger, p, now)
            for i, (node, ok) in enumerate(zip(m.nodes, passed, strict=True))
        )
        rejections: dict[str, int] = {}
    else:
        shown = _top(e.score, top_k)
        if best is not None and best not in shown:
            shown = [best, *shown[: top_k - 1]]
        out = [_scored_verdict(c, m, e, i) for i in shown]
        rejections = {}
        for f, count, before, after in e.rejected(len(m)):
            rejections[FILTERS[f]] = count
            if examples > 0:
                gone = ~after if before is None else before > after
                out += [rt_kube.node_verdict(c, m.nodes[i], m.ledger, p, now)
                        for i in np.flatnonzero(gone)[:examples].tolist()]  # fmt: skip
        verdicts = tuple(out)
    if best is None:
        return Decision(c.name, None, None, verdicts, rejections)
    return Decision(c.name, m.names[best], float(e.score[best]), verdicts, rejections)


def schedule(
    containers: Iterable[RTContainer],
    nodes: Sequence[RTNode],
    params: RTKubeParams | None = None,
    ledger: Ledger | None = None,
    now: float | None = None,
    top_k: int = TOP_K,
    full: str = "none",
    examples: int = EXAMPLES,
    explain: str | None = None,
) -> PlacementPlan:
    """One scheduler pass (``rt_kube.schedule``'s contract and choices): sort, then filter/score/bind each
    container in queue order. ``full``: ``"none"`` (bounded explanations), ``"pending"`` (every node's
    verdict for the containers left pending), ``"all"`` (every node's verdict, as the reference) or
    ``"auto"`` (``"all"`` on at most :data:`FULL_UP_TO` nodes, else ``"none"``). ``explain`` names one
    container whose decision keeps every node's verdict whatever ``full`` says: its verdicts against the
    ledger as it was at its turn in the queue, which a later :func:`why_not` (against the final ledger)
    cannot give."""
    if full not in ("none", "pending", "all", "auto"):
        raise ValueError(f"full must be none, pending, all or auto, got {full!r}")
    if full == "auto":
        full = "all" if len(nodes) <= FULL_UP_TO else "none"
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
        d = place_one(c, matrix, p, now, top_k, full == "all" or c.name == explain, examples)
        if d.node is not None:
            book.reserve(c, d.node)
            matrix.refresh(d.node)
        elif full == "pending" and c.name != explain:
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
