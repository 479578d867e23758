"""G-FL and G-FL_c: global fair-lateness scheduling of OpenVX DAGs (thesis ref. [31], 3.1.1, Table 4.2-4.4).

Mapping [TEXT]: G-FL puts every node that has a GPU kernel on the GPU (VisionWorks' local-best rule);
the operating system picks the CPU core. G-FL_c (``mapping="heft"``) keeps the CE *kind* HEFT chose for
each node and then applies the same scheduling rules.

Scheduling [PROPOSAL of spec 01 section 5.2; the thesis never states the rule]: the literature's Global
Fair-Lateness scheduler, event-driven, work-conserving and non-preemptive:
- a task is *released* once all its predecessors have finished and their data has arrived, and not
  before its frame's release;
- whenever a processor of kind k is idle, it starts the released task of kind k with the smallest key
  ``(frame, PP, tie)``, where ``PP = release + D - ((m_k - 1) / m_k) * w`` is the fair-lateness priority
  point (``m_k`` processors of kind k; the shared relative deadline D cancels out, and with one
  processor the rule is FIFO by release); earlier frames always come first (no starvation);
- idle processors are served in platform order (core 0 first).
Ties of the priority point go by input order (``tie="id"``, the node id of spec 01); ``tie="rank"`` breaks
them by HEFT's upward-rank list instead. Both reproduce every figure of spec 01 section 7.5.
Several frames (spec 01 section 5.3): with ``in_order``, a source of frame f starts only once the same
source of frame f-1 has started (Eq. 3.5) and a sink of frame f finishes no earlier than the same sink
of frame f-1 (Eq. 3.6).
"""

from __future__ import annotations

from collections.abc import Sequence

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment, Schedule
from continuum.engine.device.heft import (
    Compiled,
    Progress,
    compile_problem,
    compiled_ranks,
    priority_list,
    schedule_list,
)

__all__ = ["MAPPINGS", "TIES", "gfl", "gfl_c", "gfl_frames", "gfl_mapping"]

MAPPINGS = ("local_best", "heft")
TIES = ("id", "rank")


def gfl_mapping(
    prob: Compiled,
    mapping: str = "local_best",
    *,
    gpu_class: str = "gpu",
    rank_mode: str = "max",
    comm_mode: str = "impl",
) -> list[list[tuple[int, float]]]:
    """Per task, the (processor, time) pairs G-FL may use: those of the one kind the mapping chose."""
    procs = prob.platform.processors
    if mapping == "local_best":
        out = []
        for row in prob.costs:
            on_gpu = [(p, w) for p, w in row if procs[p].cls == gpu_class]
            out.append(on_gpu or row)
        return out
    if mapping == "heft":
        ranks = compiled_ranks(prob, rank_mode, comm_mode)
        placed = schedule_list(prob, priority_list(prob, ranks))
        kinds = [procs[p].cls for p in placed.proc]
        return [[(p, w) for p, w in row if procs[p].cls == kinds[t]] for t, row in enumerate(prob.costs)]
    raise InputError(f"unknown G-FL mapping {mapping!r} (choose from {', '.join(MAPPINGS)})", "mapping")


def gfl_frames(
    dag: TaskGraph,
    platform: Platform,
    release: Sequence[float] = (0.0,),
    *,
    mapping: str = "local_best",
    tie: str = "id",
    in_order: bool = True,
    gpu_class: str = "gpu",
    rank_mode: str = "max",
    comm_mode: str = "impl",
    progress: Progress | None = None,
) -> Schedule:
    """G-FL on ``len(release)`` frames, frame ``f`` released at ``release[f]``.

    ``progress(placed, total)`` is called about a hundred times over the run (large DAGs, many frames).
    """
    if tie not in TIES:
        raise InputError(f"unknown tie rule {tie!r} (choose from {', '.join(TIES)})", "tie")
    prob = compile_problem(dag, platform)
    allowed = gfl_mapping(prob, mapping, gpu_class=gpu_class, rank_mode=rank_mode, comm_mode=comm_mode)
    n, P, F = prob.n, len(prob.names), len(release)
    procs = prob.platform.processors
    size: dict[str, int] = {}
    for proc_ in procs:
        size[proc_.cls] = size.get(proc_.cls, 0) + 1
    share = [(size[q.cls] - 1) / size[q.cls] for q in procs]  # (m_k - 1) / m_k of processor p's kind
    if tie == "rank":
        order = priority_list(prob, compiled_ranks(prob, rank_mode, comm_mode))
        tie_of = [0] * n
        for i, t in enumerate(order):
            tie_of[t] = i
    else:
        tie_of = list(range(n))
    is_source = [not p for p in prob.pred]
    is_sink = [not s for s in prob.succ]
    lat, inv = prob.lat, prob.inv

    N = n * F
    waiting = [len(prob.pred[i % n]) for i in range(N)]
    proc = [-1] * N
    start = [0.0] * N
    finish = [0.0] * N
    # Items whose predecessors are all placed, with their (processor, time, ready time) choices: these
    # are fixed once the item is admitted, because everything they depend on is placed by then.
    candidates: dict[int, list[tuple[int, float, float]]] = {}
    blocked: dict[int, int] = {}  # item of frame f-1 -> the same task of frame f waiting for it (Eqs. 3.5-3.6)

    def ready_on(item: int, p: int, w: float) -> float:
        f, t = divmod(item, n)
        base = f * n
        r = release[f]
        for q, data in prob.pred[t]:
            qi = base + q
            a = finish[qi] + lat[proc[qi]][p] + data * inv[proc[qi]][p]
            if a > r:
                r = a
        if in_order and f:
            prev = item - n
            if is_source[t] and start[prev] > r:
                r = start[prev]
            if is_sink[t] and finish[prev] - w > r:
                r = finish[prev] - w
        return r

    def admit(item: int) -> None:
        f, t = divmod(item, n)
        if in_order and f and (is_source[t] or is_sink[t]) and proc[item - n] < 0:
            blocked[item - n] = item
        else:
            candidates[item] = [(p, w, ready_on(item, p, w)) for p, w in allowed[t]]

    for item in range(N):
        if waiting[item] == 0:
            admit(item)

    free = [0.0] * P
    now = 0.0
    placed: list[Assignment] = []
    step = max(1, N // 100)
    while len(placed) < N:
        progressed = False
        for p in range(P):
            if free[p] > now:
                continue
            best = None
            for item, opts in candidates.items():
                for q, w, r in opts:
                    if q == p and r <= now:
                        key = (item // n, round(r - share[p] * w, 9), tie_of[item % n], item)
                        if best is None or key < best[0]:
                            best = (key, item, w)
                        break
            if best is None:
                continue
            _, item, w = best
            del candidates[item]
            proc[item], start[item], finish[item] = p, now, now + w
            free[p] = now + w
            f, t = divmod(item, n)
            placed.append(Assignment(prob.ids[t], prob.names[p], now, now + w, f))
            if progress and (len(placed) % step == 0 or len(placed) == N):
                progress(len(placed), N)
            progressed = True
            for q, _ in prob.succ[t]:
                qi = f * n + q
                waiting[qi] -= 1
                if waiting[qi] == 0:
                    admit(qi)
            follower = blocked.pop(item, None)
            if follower is not None:
                admit(follower)
        if progressed:
            continue  # tasks made ready at this very instant may fit processors visited earlier
        # advance to the next event: a processor frees up or a candidate becomes ready somewhere
        nxt = [fr for fr in free if fr > now]
        for opts in candidates.values():
            for p, _, r in opts:
                if r > now:
                    nxt.append(max(r, free[p]))
        if not nxt:
            raise InputError("G-FL could not place every task (an inconsistent mapping)", "mapping")
        now = min(nxt)
    name = "gfl_c" if mapping == "heft" else "gfl"
    return Schedule(name, placed, params={"mapping": mapping, "tie": tie})


def gfl(
    dag: TaskGraph,
    platform: Platform,
    *,
    mapping: str = "local_best",
    tie: str = "id",
    gpu_class: str = "gpu",
    rank_mode: str = "max",
    comm_mode: str = "impl",
    progress: Progress | None = None,
) -> Schedule:
    """G-FL on one frame (``mapping="heft"`` for G-FL_c)."""
    return gfl_frames(
        dag,
        platform,
        (0.0,),
        mapping=mapping,
        tie=tie,
        gpu_class=gpu_class,
        rank_mode=rank_mode,
        comm_mode=comm_mode,
        progress=progress,
    )


def gfl_c(
    dag: TaskGraph,
    platform: Platform,
    *,
    tie: str = "id",
    rank_mode: str = "max",
    comm_mode: str = "impl",
    progress: Progress | None = None,
) -> Schedule:
    """G-FL_c: G-FL with HEFT's CE kinds."""
    return gfl(dag, platform, mapping="heft", tie=tie, rank_mode=rank_mode, comm_mode=comm_mode, progress=progress)
