"""Pipelined DAG execution across camera frames (thesis 3.1.1, Eqs. 3.5-3.7, Tables 4.2-4.4).

The DAG runs once per frame; scheduling ``frames`` instances together gives a bigger pool of ready tasks.
Constraints (read with ``>=`` instead of the thesis' strict inequalities, spec 01 section 5.3):
    (3.5) start(s^i) >= start(s^{i-1}) for every source s      (in-order start)
    (3.6) end(s^i)   >= end(s^{i-1})   for every sink s        (in-order completion)
    (3.7) start(s^{i+1}) - start(s^i) >= 1 / CameraFPS         (streaming only)
and every task of an earlier frame outranks every task of a later one.

Frame releases (``release[f]``, the earliest start of frame f's tasks):
- no ``fps``/``period``: every frame is already in memory, release 0 (the *batched pipeline*, the only
  variant of Tables 4.2-4.4);
- ``fps`` (or ``period`` in the DAG's time unit, ``1000/fps`` for ms): streaming, frame f released at
  ``f * period`` (Eq. 3.7; 45 FPS is the thesis' 22 ms);
- ``batch=B`` with a rate [PROPOSAL]: frames are buffered B at a time and a batch is handed over when it is
  complete, so frame f is released at ``floor(f / B) * B * period``; Eq. 3.7 holds between batches and is
  dropped inside one. ``batch >= frames`` is the batched pipeline again.

How each algorithm runs several frames (:data:`NATIVE`):
- HEFT_p / XEFT_p: the single-DAG priority list (XEFT's for XEFT) concatenated once per frame, in frame
  order, then HEFT's phase 2 with insertion, releases and Eqs. 3.5-3.6 (spec 01 section 5.3);
- G-FL / G-FL_c: the event-driven rule with every frame's tasks in the pool;
- VisionWorks: frames one after the other in its global order (with overlap: per processor);
- any other registered scheduler: its single-frame schedule repeated, each frame shifted by the smallest
  offset that respects the release, the frame order and every processor's previous frames
  (:func:`replicate`).
Metrics (``Schedule.metrics``): makespan, per-frame and mean latency (last finish minus release),
throughput, idle time per processor, frame buffers in use (Table 4.4), O/XO and, for several frames, the
pipeline gain ``(n * M_1 - M_n) / (n * M_1)`` over the same scheduler on one frame [PROPOSAL, Table 4.2].
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

from continuum.engine.core import limits
from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import EPS, Assignment, Schedule
from continuum.engine.device import overlap as ov
from continuum.engine.device.gfl import gfl_frames
from continuum.engine.device.heft import (
    Progress,
    compile_problem,
    compiled_ranks,
    priority_list,
    schedule_list,
    to_assignments,
)
from continuum.engine.device.registry import SCHEDULERS, call, unknown
from continuum.engine.device.visionworks import visionworks_frames
from continuum.engine.device.xeft import xeft_order

__all__ = ["NATIVE", "UNIT_SECONDS", "frame_metrics", "frame_violations", "pipeline", "releases", "replicate"]

#: Seconds per time unit, to turn a camera rate into a period.
UNIT_SECONDS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6}


def releases(
    frames: int = 1,
    *,
    fps: float | None = None,
    period: float | None = None,
    batch: int | None = None,
    time_unit: str = "ms",
) -> list[float]:
    """Release time of each frame (see the module docstring)."""
    if isinstance(frames, bool) or not isinstance(frames, int) or frames < 1:
        raise InputError(f"frames must be a positive integer, not {frames!r}", "frames")
    limits.check("frames", frames)
    if batch is not None and (isinstance(batch, bool) or not isinstance(batch, int) or batch < 1):
        raise InputError(f"batch must be a positive integer, not {batch!r}", "batch")
    if batch is not None:
        limits.check("batch", batch, name="frames")
    if fps is not None and period is not None:
        raise InputError("give either fps or period, not both", "fps")
    if fps is not None:
        if not (isinstance(fps, (int, float)) and fps > 0 and math.isfinite(fps)):
            raise InputError(f"fps must be a positive number, not {fps!r}", "fps")
        if time_unit not in UNIT_SECONDS:
            raise InputError(f"cannot turn fps into a period in time unit {time_unit!r}; give period", "fps")
        period = 1.0 / fps / UNIT_SECONDS[time_unit]
    if period is None:
        return [0.0] * frames
    if not (isinstance(period, (int, float)) and period >= 0 and math.isfinite(period)):
        raise InputError(f"period must be a non-negative number, not {period!r}", "period")
    b = batch or 1
    return [(f // b) * b * float(period) for f in range(frames)]


# ---- native multi-frame schedulers -----------------------------------------------------------------
def _rank_based(name: str) -> Callable[..., Schedule]:
    def run(
        dag: TaskGraph,
        platform: Platform,
        release: Sequence[float],
        *,
        in_order: bool = True,
        rank_mode: str | None = None,
        comm_mode: str | None = None,
        insertion: bool = True,
        progress: Progress | None = None,
        **params: Any,
    ) -> Schedule:
        prob = compile_problem(dag, platform)
        if name == "xeft":
            rank_mode, comm_mode = rank_mode or "max", comm_mode or "impl"
            ranks, order = xeft_order(prob, rank_mode=rank_mode, comm_mode=comm_mode, **params)
        else:
            if params:
                raise InputError(f"heft: unexpected parameter {next(iter(params))!r}", "params")
            rank_mode, comm_mode = rank_mode or "mean", comm_mode or "pairs"
            ranks = compiled_ranks(prob, rank_mode, comm_mode)
            order = priority_list(prob, ranks)
        n, frames = prob.n, len(release)
        items = [f * n + t for f in range(frames) for t in order]
        placed = schedule_list(
            prob, items, frames=frames, release=release, in_order=in_order, insertion=insertion, progress=progress
        )
        return Schedule(
            name,
            to_assignments(prob, placed),
            ranks=dict(zip(prob.ids, ranks, strict=True)),
            params={"rank_mode": rank_mode, "comm_mode": comm_mode, "insertion": insertion},
        )

    return run


def _gfl(mapping: str) -> Callable[..., Schedule]:
    def run(
        dag: TaskGraph, platform: Platform, release: Sequence[float], progress: Progress | None = None, **params: Any
    ) -> Schedule:
        params.setdefault("mapping", mapping)
        return gfl_frames(dag, platform, release, progress=progress, **params)

    return run


def _vw(overlap: bool) -> Callable[..., Schedule]:
    def run(
        dag: TaskGraph,
        platform: Platform,
        release: Sequence[float],
        *,
        in_order: bool = True,
        progress: Progress | None = None,
        **params: Any,
    ) -> Schedule:
        params.setdefault("overlap", overlap)
        return visionworks_frames(dag, platform, release, progress=progress, **params)  # frame order is built in

    return run


#: name -> function(dag, platform, release, **params) -> multi-frame Schedule.
NATIVE: dict[str, Callable[..., Schedule]] = {
    "heft": _rank_based("heft"),
    "xeft": _rank_based("xeft"),
    "gfl": _gfl("local_best"),
    "gfl_c": _gfl("heft"),
    "visionworks": _vw(False),
    "visionworks_overlap": _vw(True),
}


def replicate(single: Schedule, release: Sequence[float]) -> list[Assignment]:
    """Frame f = ``single`` shifted by the smallest offset >= release[f] and >= the previous offset that
    keeps every processor's intervals after the previous frames' ones on that processor."""
    rows = single.by_processor()
    first = {p: row[0].start for p, row in rows.items()}
    last = {p: row[-1].finish for p, row in rows.items()}
    origin = min((a.start for a in single.assignments), default=0.0)
    out: list[Assignment] = []
    shift = -math.inf
    busy_until: dict[str, float] = {}
    for f, rel in enumerate(release):
        shift = max(shift, rel - origin, *(busy_until[p] - first[p] for p in busy_until))
        for a in single.assignments:
            out.append(replace(a, start=a.start + shift, finish=a.finish + shift, frame=f))
        for p in rows:
            busy_until[p] = last[p] + shift
    return out


# ---- the entry point ------------------------------------------------------------------------------------
def pipeline(
    algorithm: str,
    dag: TaskGraph,
    platform: Platform,
    *,
    frames: int = 1,
    fps: float | None = None,
    period: float | None = None,
    batch: int | None = None,
    in_order: bool = True,
    gain: bool = True,
    progress: Progress | None = None,
    **params: Any,
) -> Schedule:
    """Schedule ``frames`` instances of ``dag`` with ``algorithm``; see the module docstring."""
    release = releases(frames, fps=fps, period=period, batch=batch, time_unit=dag.time_unit)
    most = limits.get().frame_tasks
    if len(release) * len(dag) > most:
        raise InputError(
            f"frames: at most {max(1, most // len(dag)):,} for a DAG of {len(dag):,} tasks "
            f"(frames x tasks: at most {most:,})",
            "frames",
        )
    if algorithm in NATIVE:
        schedule = call(
            algorithm, NATIVE[algorithm], dag, platform, release, in_order=in_order, progress=progress, **params
        )
    elif algorithm in SCHEDULERS:
        single = call(algorithm, SCHEDULERS[algorithm], dag, platform, progress=progress, **params)
        schedule = Schedule(algorithm, replicate(single, release), single.ranks, dict(single.params))
    else:
        raise unknown(algorithm)
    schedule.algorithm = algorithm
    schedule.params.update({"frames": frames, "in_order": in_order})
    for key, value in (("fps", fps), ("period", period), ("batch", batch)):
        if value is not None:
            schedule.params[key] = value
    schedule.metrics.update(frame_metrics(schedule, dag, platform, release))
    if gain and frames > 1:
        one = pipeline(algorithm, dag, platform, frames=1, gain=False, **params)
        m1 = one.makespan
        schedule.metrics["single_frame_makespan"] = m1
        schedule.metrics["pipeline_gain"] = (frames * m1 - schedule.makespan) / (frames * m1) if m1 else None
    return schedule


def frame_metrics(schedule: Schedule, dag: TaskGraph, platform: Platform, release: Sequence[float]) -> dict[str, Any]:
    """Makespan, latency, throughput, idle time, buffers and overlap figures of a multi-frame schedule."""
    done: dict[int, float] = {}
    for a in schedule.assignments:
        done[a.frame] = max(done.get(a.frame, a.finish), a.finish)
    latency = [done[f] - release[f] for f in range(len(release)) if f in done]
    span = schedule.makespan
    unit = UNIT_SECONDS.get(dag.time_unit)
    metrics = ov.schedule_metrics(schedule, dag, platform)
    metrics.update(
        {
            "frames": len(release),
            "releases": list(release),
            "frame_latency": latency,
            "mean_latency": sum(latency) / len(latency) if latency else 0.0,
            "throughput": len(release) / span if span > 0 else None,
            "throughput_per_s": len(release) / (span * unit) if span > 0 and unit else None,
        }
    )
    return metrics


def frame_violations(schedule: Schedule, dag: TaskGraph, release: Sequence[float], in_order: bool = True) -> list[str]:
    """What breaks the release times or Eqs. 3.5-3.6 (complements :meth:`Schedule.violations`)."""
    problems: list[str] = []
    table = schedule.lookup()
    pred = dag.predecessors()
    succ = dag.successors()
    for a in schedule.assignments:
        if a.frame >= len(release):
            problems.append(f"task {a.task!r} is in frame {a.frame}, beyond the {len(release)} frames")
        elif a.start + EPS * max(1.0, release[a.frame]) < release[a.frame]:
            problems.append(
                f"task {a.task!r} (frame {a.frame}) starts at {a.start} before its release {release[a.frame]}"
            )
    if not in_order:
        return problems
    for tid in dag.tasks:
        for f in range(1, len(release)):
            earlier, later = table.get((tid, f - 1)), table.get((tid, f))
            if earlier is None or later is None:
                continue
            if not pred[tid] and later.start + EPS * max(1.0, earlier.start) < earlier.start:
                problems.append(
                    f"source {tid!r}: frame {f} starts at {later.start} before frame {f - 1} ({earlier.start}), Eq. 3.5"
                )
            if not succ[tid] and later.finish + EPS * max(1.0, earlier.finish) < earlier.finish:
                problems.append(
                    f"sink {tid!r}: frame {f} ends at {later.finish} before frame {f - 1} ({earlier.finish}), Eq. 3.6"
                )
    return problems
