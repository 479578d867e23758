"""VisionWorks ("VW"): NVIDIA's OpenVX runtime as the thesis' baseline (3.1.1, Table 2.1, Fig. 3.2a).

Mapping, "local best": a node runs on the GPU whenever it has a GPU kernel, otherwise on the CPU. The
runtime picks neither the core nor the CPU cluster (Table 2.1), so a CPU node goes to the fastest CPU
able to run it (ties: the first in platform order); on a platform without a ``gpu_class`` processor a
node goes to its fastest processor. AMD's OpenVX behaves the same way.

Scheduling: the nodes run in topological order, breadth-first (Kahn's algorithm with a FIFO queue), the
order that reproduces the thesis' remark that overlapping would save exactly one unit on Fig. 3.1
(spec 01 section 5.1, 29 -> 28).
- ``overlap=False`` (VW proper): nothing overlaps, not even across CEs, so the makespan is the sum of the
  local-best times plus the transfers on the way [DERIVED from Table 4.1: VW = constant + DL].
- ``overlap=True``: each processor runs its own nodes in that global order, one after the other, and
  different processors run at the same time.
Several frames run in frame order: all of frame 0 in the global order, then frame 1, ...; a frame never
starts before its release.
"""

from __future__ import annotations

from collections.abc import Sequence

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment, Schedule
from continuum.engine.device.heft import Compiled, Progress, breadth_first, compile_problem

__all__ = ["local_best", "visionworks", "visionworks_frames", "visionworks_overlap"]


def local_best(prob: Compiled, gpu_class: str = "gpu") -> list[tuple[int, float]]:
    """Per task, the (processor, time) VW maps it to."""
    procs = prob.platform.processors
    out = []
    for row in prob.costs:
        on_gpu = [(p, w) for p, w in row if procs[p].cls == gpu_class]
        pool = on_gpu or row
        best = pool[0]
        for p, w in pool[1:]:
            if w < best[1]:
                best = (p, w)
        out.append(best)
    return out


def visionworks_frames(
    dag: TaskGraph,
    platform: Platform,
    release: Sequence[float] = (0.0,),
    *,
    overlap: bool = False,
    gpu_class: str = "gpu",
    progress: Progress | None = None,
) -> Schedule:
    """VW on ``len(release)`` frames, frame ``f`` released at ``release[f]``; ``progress(placed, total)``."""
    prob = compile_problem(dag, platform)
    mapping = local_best(prob, gpu_class)
    order = breadth_first(prob)
    n, P = prob.n, len(prob.names)
    lat, inv = prob.lat, prob.inv
    free = [0.0] * P  # per processor; without overlap every processor shares the one clock below
    clock = 0.0
    finish = [0.0] * (n * len(release))
    assignments = []
    total = n * len(release)
    step = max(1, total // 100)
    for f, rel in enumerate(release):
        base = f * n
        for t in order:
            p, w = mapping[t]
            ready = rel
            for q, data in prob.pred[t]:
                pq = mapping[q][0]
                arrival = finish[base + q] + lat[pq][p] + data * inv[pq][p]
                if arrival > ready:
                    ready = arrival
            s = max(ready, free[p] if overlap else clock)
            finish[base + t] = s + w
            free[p] = clock = s + w
            assignments.append(Assignment(prob.ids[t], prob.names[p], s, s + w, f))
            if progress and (len(assignments) % step == 0 or len(assignments) == total):
                progress(len(assignments), total)
    name = "visionworks_overlap" if overlap else "visionworks"
    return Schedule(name, assignments, params={"overlap": overlap})


def visionworks(
    dag: TaskGraph,
    platform: Platform,
    *,
    overlap: bool = False,
    gpu_class: str = "gpu",
    progress: Progress | None = None,
) -> Schedule:
    """VW on one frame."""
    return visionworks_frames(dag, platform, (0.0,), overlap=overlap, gpu_class=gpu_class, progress=progress)


def visionworks_overlap(
    dag: TaskGraph, platform: Platform, *, gpu_class: str = "gpu", progress: Progress | None = None
) -> Schedule:
    """VW with cross-processor overlap (spec 01 section 5.1's ``vw_overlap``)."""
    return visionworks(dag, platform, overlap=True, gpu_class=gpu_class, progress=progress)
