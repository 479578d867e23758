"""The static DAG schedulers by name, so that commands, jobs and the API offer the same list."""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Schedule
from continuum.engine.device.gfl import gfl, gfl_c
from continuum.engine.device.heft import Progress, heft
from continuum.engine.device.visionworks import visionworks, visionworks_overlap
from continuum.engine.device.xeft import xeft
from continuum.engine.heft4k.heft4k import heft4k

Scheduler = Callable[..., Schedule]

#: name -> function(dag, platform, **params) -> Schedule. Other modules register their methods here.
SCHEDULERS: dict[str, Scheduler] = {
    "heft": heft,
    "heft4k": heft4k,
    "xeft": xeft,
    "gfl": gfl,
    "gfl_c": gfl_c,
    "visionworks": visionworks,
    "visionworks_overlap": visionworks_overlap,
}
#: Parameters that make :func:`run` schedule several frames (:mod:`continuum.engine.device.pipeline`).
FRAME_PARAMS = ("frames", "fps", "period", "batch", "in_order")


def call(name: str, fn: Callable[..., Schedule], *args: Any, progress: Progress | None = None, **params: Any):
    """``fn(*args, **params)``, passing ``progress`` only when ``fn`` takes it; a wrong parameter is bad input."""
    if progress is not None and "progress" in inspect.signature(fn).parameters:
        params["progress"] = progress
    try:
        return fn(*args, **params)
    except TypeError as exc:
        if "unexpected keyword" in str(exc):
            raise InputError(f"{name}: {exc}", "params") from exc
        raise


def run(name: str, dag: TaskGraph, platform: Platform, progress: Progress | None = None, **params: Any) -> Schedule:
    """Schedule ``dag`` on ``platform`` with the algorithm called ``name``.

    ``progress(done, total)`` is passed on to the algorithms that report progress. With any of
    ``frames``, ``fps``, ``period``, ``batch`` or ``in_order``, the DAG is scheduled once per frame by
    :func:`continuum.engine.device.pipeline.pipeline`. The schedule's ``metrics`` carry the Table 4.1 figures
    (overlap, exclusive overlap, idle time, SLR, buffers used).
    """
    if name not in SCHEDULERS:
        raise InputError(f"unknown algorithm {name!r} (choose from {', '.join(sorted(SCHEDULERS))})", "algorithm")
    if any(k in params for k in FRAME_PARAMS):
        from continuum.engine.device.pipeline import pipeline

        return pipeline(name, dag, platform, progress=progress, **params)
    from continuum.engine.device.overlap import schedule_metrics

    schedule = call(name, SCHEDULERS[name], dag, platform, progress=progress, **params)
    for key, value in schedule_metrics(schedule, dag, platform).items():
        schedule.metrics.setdefault(key, value)
    return schedule
