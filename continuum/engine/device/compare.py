"""Several schedulers side by side on one DAG and platform (thesis Tables 4.1 and 4.3, spec 01 section 6).

Per algorithm: makespan, SLR, speedup against VisionWorks with Table 4.1's convention
``(M_VW - M) / M_VW``, overlap O(A), exclusive overlap XO(A) and its efficiency, idle time (overall and per
processor), buffers used and, for several frames, mean latency and the pipeline gain. ``relative`` is
Table 4.3: the cell (row A, column B) is ``M_B / M_A - 1``, how much faster A is than B. The rank-based
algorithms and G-FL_c's HEFT mapping all use the same rank reading (by default the thesis' ``max`` cost
and implementation-kind transfers, spec 01 section 2.1) so that the comparison is like for like. The
result is a plain JSON-able dict; the scheduling app turns it into a job and charts.

Long runs: ``progress(algorithm, index, count, done, total)`` reports, per algorithm (``index`` of
``count``, the reference included when it is not in the list), the tasks placed so far (``done`` of
``total``; ``0, 0`` when the algorithm starts). ``on_schedule(algorithm, schedule)`` receives every
:class:`~continuum.engine.core.schedule.Schedule` made, so a caller can store them without running again.
"""

from __future__ import annotations

import inspect
import time
from collections.abc import Callable, Sequence
from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Schedule
from continuum.engine.device import overlap as ov
from continuum.engine.device.pipeline import pipeline
from continuum.engine.device.registry import SCHEDULERS

__all__ = ["DEFAULT_ALGORITHMS", "FIGURES", "REFERENCE", "CompareProgress", "compare"]

#: ``progress(algorithm, index, count, done, total)``, see the module docstring.
CompareProgress = Callable[[str, int, int, int, int], None]

DEFAULT_ALGORITHMS = ("visionworks", "gfl", "gfl_c", "heft", "xeft")
REFERENCE = "visionworks"
FIGURES = ("overlap", "xo", "max_xo", "xo_efficiency", "idle", "idle_per_processor", "buffers_used")


def compare(
    dag: TaskGraph,
    platform: Platform,
    algorithms: Sequence[str] = DEFAULT_ALGORITHMS,
    *,
    frames: int = 1,
    fps: float | None = None,
    period: float | None = None,
    batch: int | None = None,
    rank_mode: str = "max",
    comm_mode: str = "impl",
    progress: CompareProgress | None = None,
    on_schedule: Callable[[str, Schedule], None] | None = None,
) -> dict[str, Any]:
    """Run ``algorithms`` on ``dag`` and ``platform``; see the module docstring for the figures."""
    if not algorithms:
        raise InputError("choose at least one algorithm", "algorithms")
    unknown = [a for a in algorithms if a not in SCHEDULERS]
    if unknown:
        raise InputError(
            f"unknown algorithm {unknown[0]!r} (choose from {', '.join(sorted(SCHEDULERS))})", "algorithms"
        )
    frame_args = {"frames": frames, "fps": fps, "period": period, "batch": batch}
    results: dict[str, dict[str, Any]] = {}
    names = list(dict.fromkeys([*algorithms, REFERENCE]))  # the reference always runs, once
    for index, name in enumerate(names):
        accepted = inspect.signature(SCHEDULERS[name]).parameters
        params: dict[str, Any] = {
            k: v for k, v in (("rank_mode", rank_mode), ("comm_mode", comm_mode)) if k in accepted
        }
        report = None
        if progress is not None:
            progress(name, index, len(names), 0, 0)

            def report(done: int, total: int, name: str = name, index: int = index) -> None:
                progress(name, index, len(names), done, total)

        started = time.perf_counter()
        schedule = pipeline(
            name, dag, platform, progress=report, frames=frames, fps=fps, period=period, batch=batch, **params
        )
        elapsed = time.perf_counter() - started
        if on_schedule is not None:
            on_schedule(name, schedule)
        m = schedule.metrics
        row: dict[str, Any] = {"makespan": schedule.makespan, "slr": m["slr"], "runtime_s": elapsed}
        row.update({k: m[k] for k in FIGURES})
        if frames > 1:
            row.update({k: m.get(k) for k in ("mean_latency", "throughput", "pipeline_gain")})
        results[name] = row
    reference = results[REFERENCE]["makespan"]
    for row in results.values():
        row["speedup_vs_visionworks"] = ov.reduction(reference, row["makespan"])
    shown = {name: results[name] for name in algorithms}
    relative = {
        a: {b: ov.relative_speed(shown[a]["makespan"], shown[b]["makespan"]) for b in shown if b != a} for a in shown
    }
    best = min(shown, key=lambda name: (shown[name]["makespan"], list(shown).index(name)))
    return {
        "dag": dag.name,
        "tasks": len(dag),
        "processors": [{"id": p.id, "class": p.cls, "speed": p.speed} for p in platform.processors],
        "frames": frames,
        "params": {"rank_mode": rank_mode, "comm_mode": comm_mode, **{k: v for k, v in frame_args.items() if v}},
        "reference": REFERENCE,
        "reference_makespan": reference,
        "results": shown,
        "relative": relative,
        "best": best,
    }
