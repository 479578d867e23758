"""Overlap, exclusive overlap and the other schedule metrics of thesis Table 4.1 (Eqs. 3.1-3.4).

    O(t, q)  = max(0, min(t_end, q_end) - max(t_start, q_start))                           (Eq. 3.1)
    XO(t, q) = O(t, q) when one of t, q runs only on the CPU and the other only on the GPU, else 0   (3.2)
    O(A)  = sum of O(t, q)  over unordered pairs of distinct tasks                              (3.3)
    XO(A) = sum of XO(t, q) over unordered pairs of distinct tasks                              (3.4)

The thesis writes the sums over ``t, q in A``; spec 01 section 3.2 reads them as unordered pairs of
distinct tasks, the only reading consistent with the Max_XO column of Table 4.1. The pair sums are
computed with a sweep: if k tasks run at an instant, they contribute k(k-1)/2 to O(A)'s integrand, and
XO(A)'s integrand is the product of the numbers of running exclusive tasks of two different classes.
This generalises "CPU-only x GPU-only" to any processor classes: a task is *exclusive* when the
processors able to run it all have one class.

Other Table 4.1 metrics (spec 01 section 3.3):
- ``max_xo = min(m_cpu * T_gpu_excl, m_gpu * T_cpu_excl)`` [DERIVED, with m_gpu = 1 in the thesis], summed
  over pairs of classes; T_x_excl is the total time of the tasks exclusive to class x (on the slowest
  processor of that class, so that the bound holds with per-core speeds), times the number of frames;
- ``xo_efficiency = XO(A) / max_xo``;
- ``idle = 1 - busy / (CPUs * makespan)`` [PROPOSAL: the thesis does not define it], where a multi-core
  processor (``Processor.cores``, HEFT4K's cluster nodes) counts each of its CPUs;
- ``slr = makespan / CP_min``, CP_min the longest path with each task's fastest time, no transfers;
- ``buffers_used``: the largest number of frames whose lifetimes ``[min start, max finish)`` overlap
  (spec 01 section 5.4, Table 4.4).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment, Schedule

__all__ = [
    "buffers_used",
    "busy_per_processor",
    "cp_min",
    "exclusive_classes",
    "exclusive_overlap",
    "frame_lifetimes",
    "idle_fraction",
    "idle_per_processor",
    "max_xo",
    "overlap",
    "pair_overlap",
    "reduction",
    "relative_speed",
    "schedule_metrics",
    "slr",
]


def exclusive_classes(dag: TaskGraph, platform: Platform) -> dict[str, str | None]:
    """Task id -> the one processor class able to run it, or ``None`` when several classes can."""
    out: dict[str, str | None] = {}
    for tid, task in dag.tasks.items():
        classes = {p.cls for p in platform.processors if platform.cost(task, p) is not None}
        out[tid] = next(iter(classes)) if len(classes) == 1 else None
    return out


def _sweep(assignments: Iterable[Assignment], tag: dict[str, str | None] | None) -> tuple[float, float]:
    """(O(A), XO(A)) of ``assignments``; ``tag`` maps a task to its exclusive class (XO is 0 without it)."""
    events: list[tuple[float, int, str | None]] = []
    for a in assignments:
        if a.finish > a.start:
            cls = tag.get(a.task) if tag else None
            events.append((a.start, 1, cls))
            events.append((a.finish, -1, cls))
    events.sort(key=lambda e: (e[0], e[1]))
    o = xo = 0.0
    running = 0
    excl: dict[str, int] = {}
    prev = None
    for time, delta, cls in events:
        if prev is not None and time > prev:
            dt = time - prev
            if running > 1:
                o += dt * running * (running - 1) / 2
            if len(excl) > 1:
                counts = [c for c in excl.values() if c]
                total = sum(counts)
                # sum over pairs of classes of n_a * n_b = (total^2 - sum n_a^2) / 2
                xo += dt * (total * total - sum(c * c for c in counts)) / 2
        running += delta
        if cls is not None:
            excl[cls] = excl.get(cls, 0) + delta
        prev = time
    return o, xo


def overlap(schedule: Schedule) -> float:
    """O(A), Eq. 3.3."""
    return _sweep(schedule.assignments, None)[0]


def exclusive_overlap(schedule: Schedule, dag: TaskGraph, platform: Platform) -> float:
    """XO(A), Eq. 3.4."""
    return _sweep(schedule.assignments, exclusive_classes(dag, platform))[1]


def pair_overlap(a: Assignment, b: Assignment) -> float:
    """O(t, q), Eq. 3.1."""
    return max(0.0, min(a.finish, b.finish) - max(a.start, b.start))


def max_xo(dag: TaskGraph, platform: Platform, frames: int = 1) -> float:
    """The largest XO(A) any schedule could reach (spec 01 section 3.3), summed over pairs of classes."""
    count: dict[str, int] = {}
    for p in platform.processors:
        count[p.cls] = count.get(p.cls, 0) + 1
    totals: dict[str, float] = dict.fromkeys(count, 0.0)
    for tid, cls in exclusive_classes(dag, platform).items():
        if cls is None:
            continue
        task = dag.tasks[tid]
        times = [c for p in platform.processors if p.cls == cls and (c := platform.cost(task, p)) is not None]
        totals[cls] += max(times)
    classes = sorted(count)
    bound = 0.0
    for i, a in enumerate(classes):
        for b in classes[i + 1 :]:
            bound += min(count[a] * totals[b], count[b] * totals[a])
    return bound * frames


def busy_per_processor(schedule: Schedule, platform: Platform) -> dict[str, float]:
    busy = {p.id: 0.0 for p in platform.processors}
    for a in schedule.assignments:
        busy[a.processor] = busy.get(a.processor, 0.0) + (a.finish - a.start)
    return busy


def _cpus(platform: Platform) -> dict[str, int]:
    return {p.id: max(1, p.cores) for p in platform.processors}


def idle_per_processor(schedule: Schedule, platform: Platform) -> dict[str, float]:
    """Makespan minus busy time, per processor (Table 4.4's idle periods); a multi-core processor's idle
    time is summed over its CPUs (``cores * makespan - busy``), so it never goes negative."""
    span = schedule.makespan
    cpus = _cpus(platform)
    return {p: cpus.get(p, 1) * span - b for p, b in busy_per_processor(schedule, platform).items()}


def idle_fraction(schedule: Schedule, platform: Platform) -> float:
    """``1 - busy / (CPUs * makespan)`` [PROPOSAL]; 0 for an empty schedule."""
    span = schedule.makespan
    if span <= 0:
        return 0.0
    busy = sum(busy_per_processor(schedule, platform).values())
    return 1.0 - busy / (sum(_cpus(platform).values()) * span)


def cp_min(dag: TaskGraph, platform: Platform) -> float:
    """Longest path using each task's fastest implementation, transfers left out."""
    fastest = {tid: min(c for _, c in row) for tid, row in platform.cost_table(dag).items()}
    pred = dag.predecessors()
    longest: dict[str, float] = {}
    for tid in dag.topological_order():
        longest[tid] = fastest[tid] + max((longest[e.src] for e in pred[tid]), default=0.0)
    return max(longest.values(), default=0.0)


def slr(schedule: Schedule, dag: TaskGraph, platform: Platform) -> float | None:
    """Schedule length ratio: makespan / CP_min (of one DAG instance, whatever the number of frames)."""
    cp = cp_min(dag, platform)
    return schedule.makespan / cp if cp > 0 else None


def frame_lifetimes(schedule: Schedule) -> dict[int, tuple[float, float]]:
    """Frame -> ``(min start, max finish)`` of its assignments."""
    spans: dict[int, tuple[float, float]] = {}
    for a in schedule.assignments:
        lo, hi = spans.get(a.frame, (a.start, a.finish))
        spans[a.frame] = (min(lo, a.start), max(hi, a.finish))
    return spans


def buffers_used(schedule: Schedule) -> int:
    """Largest number of frame lifetimes overlapping at an instant (half-open intervals), Table 4.4."""
    events = []
    for lo, hi in frame_lifetimes(schedule).values():
        events.append((lo, 1))
        events.append((hi, -1))
    events.sort()  # at equal times -1 sorts first: a lifetime ending at t frees its buffer for one starting at t
    best = cur = 0
    for _, d in events:
        cur += d
        best = max(best, cur)
    return best


def reduction(reference: float, new: float) -> float | None:
    """``(M_ref - M_new) / M_ref``: Table 4.1's "X on Y" speedup (spec 01 section 6)."""
    return (reference - new) / reference if reference else None


def relative_speed(row: float, column: float) -> float | None:
    """``M_column / M_row - 1``: Table 4.3's cell for the row scheduler against the column one."""
    return column / row - 1 if row else None


def schedule_metrics(schedule: Schedule, dag: TaskGraph, platform: Platform) -> dict[str, Any]:
    """The Table 4.1 figures of one schedule (JSON-able)."""
    frames = len({a.frame for a in schedule.assignments}) or 1
    o, xo = _sweep(schedule.assignments, exclusive_classes(dag, platform))
    bound = max_xo(dag, platform, frames)
    return {
        "makespan": schedule.makespan,
        "overlap": o,
        "xo": xo,
        "max_xo": bound,
        "xo_efficiency": xo / bound if bound > 0 else None,
        "idle": idle_fraction(schedule, platform),
        "idle_per_processor": idle_per_processor(schedule, platform),
        "slr": slr(schedule, dag, platform),
        "buffers_used": buffers_used(schedule),
    }
