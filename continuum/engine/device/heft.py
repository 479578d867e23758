"""HEFT: Heterogeneous Earliest Finish Time (Topcuoglu, Hariri & Wu, TPDS 2002; thesis Eq. 2.1, 3.1.1).

Phase 1 ranks every task by its upward rank
    rank(t) = w_bar(t) + max_{q in succ(t)} (c_bar(t, q) + rank(q))                       (Eq. 2.1)
Phase 2 takes the tasks by decreasing rank and puts each on the processor where it finishes earliest,
inserting it into an idle gap when one is long enough (the insertion policy of the original paper).

Readings and rules, all parameters so that they can be changed (thesis ambiguity, spec 01 section 2):
- ``rank_mode="mean"``: w_bar is the mean cost over the processors that can run the task (the
  literature; reproduces the Topcuoglu ranks 108, 77, ...). ``"max"`` takes the largest implementation
  cost, the reading that reproduces the ranks printed in the thesis' Fig. 3.1.
- ``comm_mode="pairs"``: c_bar is the mean transfer time over ordered pairs of distinct processors (0 with
  one processor), the literature's reading. ``"impl"`` is spec 01 section 2.1: the mean, over the pairs
  (class able to run t, class able to run q), of the mean transfer time between distinct processors of
  those two classes. On a board whose CPU cores share memory this is ``transfer`` when the classes differ
  and 0 when they are equal.
- Task ties: among the tasks whose predecessors are all placed, the highest rank goes first, and equal
  ranks go in input order. Picking only among ready tasks keeps precedence even when zero costs make a
  successor's rank equal to its predecessor's. The resulting order does not depend on the placements, so
  it is computed up front (:func:`priority_list`) and phase 2 is a plain list scheduler
  (:func:`schedule_list`), shared with XEFT and the pipelined variants.
- Processor ties: processors are tried in platform order and a later one wins only with a strictly
  smaller finish time, so ties go to the first processor (the CPU, core 0, in the thesis' platforms).

Speed (measured, see ``benchmarks/heft_vs_saga.py``): the DAG is compiled once into integer-indexed
lists; ready times use a closed form when all transfers are free or every pair of distinct processors has
the same link (O(in-degree + processors) per task instead of O(in-degree x processors)), and numpy over
processors for per-link transfers from :data:`VECTOR_FROM` processors on; a processor whose lower bound
cannot beat the best finish time so far is skipped; the insertion search walks each processor's idle
gaps instead of its busy intervals, and appending after the last one skips the search. None of this
changes a result.
"""

from __future__ import annotations

import heapq
from bisect import bisect_right
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment, Schedule

__all__ = [
    "COMM_MODES",
    "RANK_MODES",
    "VECTOR_FROM",
    "Compiled",
    "Placed",
    "Progress",
    "breadth_first",
    "compile_problem",
    "compiled_ranks",
    "earliest_slot",
    "heft",
    "priority_list",
    "schedule_list",
    "to_assignments",
    "upward_ranks",
]

Progress = Callable[[int, int], None]
#: From this many processors, per-link ready times are computed with numpy (measured faster from here).
VECTOR_FROM = 48
RANK_MODES = ("mean", "max")
COMM_MODES = ("pairs", "impl")


@dataclass
class Compiled:
    """A DAG and a platform turned into integer-indexed lists for the schedulers' inner loops."""

    dag: TaskGraph
    platform: Platform
    ids: list[str]
    names: list[str]
    #: Per task, the (processor index, time) pairs it can run on, in platform order.
    costs: list[list[tuple[int, float]]]
    #: Per task, (predecessor index, data) and (successor index, data).
    pred: list[list[tuple[int, float]]]
    succ: list[list[tuple[int, float]]]
    lat: list[list[float]]
    inv: list[list[float]]
    #: "free" (no transfer ever costs), "uniform" (every pair of distinct processors alike) or "general".
    comm: str
    lat0: float = 0.0
    inv0: float = 0.0

    @property
    def n(self) -> int:
        return len(self.ids)

    def sources(self) -> list[int]:
        return [t for t in range(self.n) if not self.pred[t]]

    def sinks(self) -> list[int]:
        return [t for t in range(self.n) if not self.succ[t]]

    def classes(self, t: int) -> list[str]:
        """Processor classes able to run task ``t``, in platform order, without repeats."""
        seen: list[str] = []
        for p, _ in self.costs[t]:
            c = self.platform.processors[p].cls
            if c not in seen:
                seen.append(c)
        return seen


def compile_problem(dag: TaskGraph, platform: Platform) -> Compiled:
    """Index ``dag`` and ``platform``; rejects a task that no processor can run."""
    ids = list(dag.tasks)
    costs = _cost_rows(dag, platform)
    index = {tid: i for i, tid in enumerate(ids)}
    pred: list[list[tuple[int, float]]] = [[] for _ in ids]
    succ: list[list[tuple[int, float]]] = [[] for _ in ids]
    for e in dag.edges:
        s, d = index[e.src], index[e.dst]
        pred[d].append((s, e.data))
        succ[s].append((d, e.data))
    lat, inv = platform.comm_matrices()
    P = len(platform.processors)
    off = {(lat[i][j], inv[i][j]) for i in range(P) for j in range(P) if i != j}
    comm, lat0, inv0 = "general", 0.0, 0.0
    if not off or off == {(0.0, 0.0)}:
        comm = "free"
    elif len(off) == 1:
        comm = "uniform"
        lat0, inv0 = next(iter(off))
    return Compiled(
        dag=dag,
        platform=platform,
        ids=ids,
        names=[p.id for p in platform.processors],
        costs=costs,
        pred=pred,
        succ=succ,
        lat=lat,
        inv=inv,
        comm=comm,
        lat0=lat0,
        inv0=inv0,
    )


def _cost_rows(dag: TaskGraph, platform: Platform) -> list[list[tuple[int, float]]]:
    """:meth:`Platform.cost_table` as a list by task index, without a method call per (task, processor)."""
    procs = [(i, p.id, p.cls, p.speed) for i, p in enumerate(platform.processors)]
    proc_ids = {p.id for p in platform.processors}
    by_class: dict[str, list[tuple[int, float]]] = {}
    for i, _, cls, speed in procs:
        by_class.setdefault(cls, []).append((i, speed))
    rows = []
    for task in dag.tasks.values():
        cost = task.cost
        if proc_ids.isdisjoint(cost):
            row: list[tuple[int, float]] = []
            matched = 0
            for key, c in cost.items():
                group = by_class.get(key)
                if group:
                    row += [(i, c / speed) for i, speed in group]
                    matched += 1
            if matched > 1:
                row.sort()  # back to platform order
        else:
            row = []
            for i, pid, cls, speed in procs:
                own = cost.get(pid)
                if own is None:
                    class_cost = cost.get(cls)
                    if class_cost is None:
                        continue
                    own = class_cost / speed
                row.append((i, own))
        if not row:
            keys = ", ".join(sorted(cost))
            raise InputError(f"task {task.id!r} cannot run on any processor (its costs name {keys})", "tasks")
        rows.append(row)
    return rows


# ---- phase 1: ranks and the priority list ------------------------------------------------------------
def _class_comm(prob: Compiled) -> dict[tuple[str, str], tuple[float, float]]:
    """Mean (latency, 1/bandwidth) between distinct processors of each pair of classes (0 if none)."""
    procs = prob.platform.processors
    sums: dict[tuple[str, str], list[float]] = {}
    for i, a in enumerate(procs):
        for j, b in enumerate(procs):
            acc = sums.setdefault((a.cls, b.cls), [0.0, 0.0, 0])
            if i != j:
                acc[0] += prob.lat[i][j]
                acc[1] += prob.inv[i][j]
                acc[2] += 1
    return {k: ((v[0] / v[2], v[1] / v[2]) if v[2] else (0.0, 0.0)) for k, v in sums.items()}


def compiled_ranks(prob: Compiled, rank_mode: str = "mean", comm_mode: str = "pairs") -> list[float]:
    """Upward ranks (Eq. 2.1) by task index."""
    if rank_mode not in RANK_MODES:
        raise InputError(f"unknown rank mode {rank_mode!r} (choose from {', '.join(RANK_MODES)})", "rank_mode")
    if comm_mode not in COMM_MODES:
        raise InputError(f"unknown comm mode {comm_mode!r} (choose from {', '.join(COMM_MODES)})", "comm_mode")
    n = prob.n
    ranks = [0.0] * n
    order = breadth_first(prob)
    if comm_mode == "pairs":
        mean_lat, mean_inv = prob.platform.mean_comm()
        has_comm = bool(mean_lat or mean_inv)
        for t in reversed(order):
            row = prob.costs[t]
            w = max(c for _, c in row) if rank_mode == "max" else sum(c for _, c in row) / len(row)
            tail = 0.0
            for q, data in prob.succ[t]:
                c_bar = mean_lat + data * mean_inv if has_comm else 0.0
                v = c_bar + ranks[q]
                if v > tail:
                    tail = v
            ranks[t] = w + tail
        return ranks
    pair = _class_comm(prob)
    kinds = [prob.classes(t) for t in range(n)]
    for t in reversed(order):
        row = prob.costs[t]
        w = max(c for _, c in row) if rank_mode == "max" else sum(c for _, c in row) / len(row)
        tail = 0.0
        for q, data in prob.succ[t]:
            combos = [pair[(a, b)] for a in kinds[t] for b in kinds[q]]
            c_bar = sum(la + data * iv for la, iv in combos) / len(combos)
            tail = max(tail, c_bar + ranks[q])
        ranks[t] = w + tail
    return ranks


def breadth_first(prob: Compiled) -> list[int]:
    """Kahn's algorithm with a FIFO queue, sources in input order: a topological order of task indices."""
    indeg = [len(p) for p in prob.pred]
    ready = [t for t in range(prob.n) if indeg[t] == 0]
    i = 0
    while i < len(ready):
        t = ready[i]
        i += 1
        for q, _ in prob.succ[t]:
            indeg[q] -= 1
            if indeg[q] == 0:
                ready.append(q)
    return ready


def upward_ranks(
    dag: TaskGraph,
    platform: Platform,
    rank_mode: str = "mean",
    costs: dict | None = None,
    comm_mode: str = "pairs",
) -> dict[str, float]:
    """The upward rank of every task (Eq. 2.1). ``costs`` is accepted for compatibility and ignored."""
    prob = compile_problem(dag, platform)
    ranks = compiled_ranks(prob, rank_mode, comm_mode)
    return dict(zip(prob.ids, ranks, strict=True))


def priority_list(prob: Compiled, ranks: Sequence[float]) -> list[int]:
    """HEFT's order: repeatedly the ready task with the highest rank, equal ranks in input order.

    Ranks are compared rounded so that float noise does not break ties that are exact on paper.
    """
    waiting = [len(p) for p in prob.pred]
    key = [-round(r, 9) for r in ranks]
    heap = [(key[t], t) for t in range(prob.n) if waiting[t] == 0]
    heapq.heapify(heap)
    order: list[int] = []
    while heap:
        _, t = heapq.heappop(heap)
        order.append(t)
        for q, _ in prob.succ[t]:
            waiting[q] -= 1
            if waiting[q] == 0:
                heapq.heappush(heap, (key[q], q))
    return order


# ---- phase 2: the list scheduler -----------------------------------------------------------------------
def earliest_slot(starts: list[float], finishes: list[float], ready: float, duration: float) -> float:
    """Earliest start >= ``ready`` of an idle gap of ``duration`` among sorted busy intervals."""
    s = ready
    for k in range(bisect_right(finishes, ready), len(starts)):
        if s + duration <= starts[k]:
            return s
        if finishes[k] > s:
            s = finishes[k]
    return s


@dataclass
class Placed:
    """The outcome of :func:`schedule_list`, indexed by ``frame * n + task``."""

    proc: list[int]
    start: list[float]
    finish: list[float]
    #: The items (``frame * n + task``) in the order they were placed.
    order: list[int]


def schedule_list(
    prob: Compiled,
    order: Sequence[int],
    *,
    frames: int = 1,
    release: Sequence[float] | None = None,
    in_order: bool = True,
    insertion: bool = True,
    allowed: Sequence[Sequence[tuple[int, float]]] | None = None,
    progress: Progress | None = None,
) -> Placed:
    """Place the items of ``order`` (``frame * n + task``) one by one where each finishes earliest.

    ``release[f]`` is the earliest start of frame ``f``'s tasks. With ``in_order`` and several frames,
    a source starts no earlier than the same source of the previous frame (Eq. 3.5) and a sink finishes
    no earlier than the same sink of the previous frame (Eq. 3.6); the thesis' strict inequalities are
    read as ``>=`` (spec 01 section 5.3). ``allowed`` restricts each task's (processor, time) choices,
    e.g. to one class for G-FL_c's mapping; by default every implementation is a choice.
    """
    n, P = prob.n, len(prob.names)
    N = n * frames
    proc = [-1] * N
    start = [0.0] * N
    finish = [0.0] * N
    starts: list[list[float]] = [[] for _ in range(P)]
    finishes: list[list[float]] = [[] for _ in range(P)]
    # The idle gaps before each processor's last finish, as parallel sorted lists of starts and ends: the
    # insertion search walks gaps rather than busy intervals (far fewer on a dense processor).
    gap_start: list[list[float]] = [[] for _ in range(P)]
    gap_end: list[list[float]] = [[] for _ in range(P)]
    choices = allowed if allowed is not None else prob.costs
    pred, lat, inv = prob.pred, prob.lat, prob.inv
    comm, lat0, inv0 = prob.comm, prob.lat0, prob.inv0
    is_source = [not p for p in pred] if frames > 1 and in_order else None
    is_sink = [not s for s in prob.succ] if frames > 1 and in_order else None
    total, step = len(order), max(1, len(order) // 100)
    # Per-link transfers with many processors: vectorise the ready times over processors.
    vector = comm == "general" and P >= VECTOR_FROM
    if vector:
        lat_np, inv_np = np.array(lat), np.array(inv)
    placed: list[int] = []
    inf = float("inf")

    for item in order:
        f, t = divmod(item, n)
        base = f * n
        lower = release[f] if release is not None else 0.0
        min_finish = 0.0
        if f and is_source is not None and is_sink is not None:
            prev = item - n
            if is_source[t] and proc[prev] >= 0 and start[prev] > lower:
                lower = start[prev]
            if is_sink[t] and proc[prev] >= 0:
                min_finish = finish[prev]
        preds = pred[t]
        # Ready time per processor, in one of three ways (see the module docstring).
        ready_all = lower
        local: dict[int, float] | None = None
        top_p, top_v, second_v = -1, lower, lower
        general = None
        by_proc = None
        if preds:
            if comm == "free":
                for q, _ in preds:
                    a = finish[base + q]
                    if a > ready_all:
                        ready_all = a
            elif comm == "uniform":
                local = {}
                remote: dict[int, float] = {}
                for q, data in preds:
                    qi = base + q
                    a = finish[qi]
                    pq = proc[qi]
                    if a > local.get(pq, lower):
                        local[pq] = a
                    r = a + lat0 + data * inv0
                    if r > remote.get(pq, lower):
                        remote[pq] = r
                for pq, r in remote.items():
                    if r > top_v:
                        second_v, top_p, top_v = top_v, pq, r
                    elif r > second_v:
                        second_v = r
            elif vector:
                # numpy over processors: one (predecessors x processors) arrival matrix, max per column
                qs = [proc[base + q] for q, _ in preds]
                arrivals = np.array([finish[base + q] for q, _ in preds])[:, None] + lat_np[qs]
                arrivals += np.array([d for _, d in preds])[:, None] * inv_np[qs]
                by_proc = arrivals.max(axis=0).tolist()
            else:
                general = [(finish[base + q], proc[base + q], data) for q, data in preds]
        best_p, best_s, best_f = -1, 0.0, inf
        for p, w in choices[t]:
            if local is not None:
                ready = second_v if top_p == p else top_v
                lp = local.get(p)
                if lp is not None and lp > ready:
                    ready = lp
            elif by_proc is not None:
                ready = by_proc[p] if by_proc[p] > lower else lower
            elif general is not None:
                ready = lower
                for a, pq, data in general:
                    arrival = a + lat[pq][p] + data * inv[pq][p]
                    if arrival > ready:
                        ready = arrival
            else:
                ready = ready_all
            if min_finish and min_finish - w > ready:
                ready = min_finish - w
            if ready + w >= best_f:
                continue  # cannot win: the start only grows from here and ties go to earlier processors
            fp = finishes[p]
            s = ready
            if fp and s < fp[-1]:
                if not insertion:
                    s = fp[-1]
                elif w > 0:
                    ge = gap_end[p]
                    gs = gap_start[p]
                    for k in range(bisect_right(ge, s), len(ge)):
                        a = gs[k]
                        st = a if a > s else s
                        if st + w <= ge[k]:
                            s = st
                            break
                    else:
                        s = fp[-1]
                else:  # a zero-length task may sit on a boundary between two busy intervals
                    s = earliest_slot(starts[p], fp, s, w)
            if s + w < best_f:
                best_p, best_s, best_f = p, s, s + w
        if best_p < 0:
            raise InputError(f"task {prob.ids[t]!r} has no processor it may run on", "tasks")
        # Intervals ending by the new start go before it; this keeps starts and finishes both sorted,
        # zero-length tasks included.
        fp = finishes[best_p]
        if not fp or best_s >= fp[-1]:
            end = fp[-1] if fp else 0.0
            if best_s > end:
                gap_start[best_p].append(end)
                gap_end[best_p].append(best_s)
            starts[best_p].append(best_s)
            fp.append(best_f)
        else:
            at = bisect_right(fp, best_s)
            starts[best_p].insert(at, best_s)
            fp.insert(at, best_f)
            gs, ge = gap_start[best_p], gap_end[best_p]
            k = bisect_right(ge, best_s)
            if k < len(ge) and gs[k] <= best_s:  # split the gap the task went into
                a, b = gs[k], ge[k]
                pieces = [(x, y) for x, y in ((a, best_s), (best_f, b)) if y > x]
                gs[k : k + 1] = [x for x, _ in pieces]
                ge[k : k + 1] = [y for _, y in pieces]
        proc[item], start[item], finish[item] = best_p, best_s, best_f
        placed.append(item)
        if progress and (len(placed) % step == 0 or len(placed) == total):
            progress(len(placed), total)
    return Placed(proc, start, finish, placed)


def to_assignments(prob: Compiled, placed: Placed) -> list[Assignment]:
    """The placed items as :class:`Assignment` objects, in placement order."""
    n, ids, names = prob.n, prob.ids, prob.names
    out = []
    for item in placed.order:
        f, t = divmod(item, n)
        out.append(Assignment(ids[t], names[placed.proc[item]], placed.start[item], placed.finish[item], f))
    return out


def heft(
    dag: TaskGraph,
    platform: Platform,
    *,
    rank_mode: str = "mean",
    comm_mode: str = "pairs",
    insertion: bool = True,
    progress: Progress | None = None,
) -> Schedule:
    """Schedule ``dag`` on ``platform`` with HEFT; returns a single-frame :class:`Schedule`."""
    prob = compile_problem(dag, platform)
    ranks = compiled_ranks(prob, rank_mode, comm_mode)
    placed = schedule_list(prob, priority_list(prob, ranks), insertion=insertion, progress=progress)
    params: dict = {"rank_mode": rank_mode, "insertion": insertion}
    if comm_mode != "pairs":
        params["comm_mode"] = comm_mode
    return Schedule(
        "heft",
        to_assignments(prob, placed),
        ranks=dict(zip(prob.ids, ranks, strict=True)),
        params=params,
    )
