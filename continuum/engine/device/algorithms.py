"""Run a static DAG scheduler by name: one frame, or several through :mod:`continuum.engine.device.pipeline`.

The names live in :mod:`continuum.engine.device.registry` (re-exported here as ``SCHEDULERS``).
"""

from __future__ import annotations

from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Schedule
from continuum.engine.device.heft import Progress
from continuum.engine.device.overlap import schedule_metrics
from continuum.engine.device.pipeline import pipeline
from continuum.engine.device.registry import SCHEDULERS, Scheduler, call, register, unknown

__all__ = ["FRAME_PARAMS", "SCHEDULERS", "Scheduler", "call", "register", "run"]

#: Parameters that make :func:`run` schedule several frames (:mod:`continuum.engine.device.pipeline`).
FRAME_PARAMS = ("frames", "fps", "period", "batch", "in_order")


def run(name: str, dag: TaskGraph, platform: Platform, progress: Progress | None = None, **params: Any) -> Schedule:
    """Schedule ``dag`` on ``platform`` with the algorithm called ``name``.

    ``progress(done, total)`` is passed on to the algorithms that report progress. With any of
    ``frames``, ``fps``, ``period``, ``batch`` or ``in_order``, the DAG is scheduled once per frame by
    :func:`continuum.engine.device.pipeline.pipeline`. The schedule's ``metrics`` carry the Table 4.1 figures
    (overlap, exclusive overlap, idle time, SLR, buffers used).
    """
    if name not in SCHEDULERS:
        raise unknown(name)
    if any(k in params for k in FRAME_PARAMS):
        return pipeline(name, dag, platform, progress=progress, **params)
    schedule = call(name, SCHEDULERS[name], dag, platform, progress=progress, **params)
    for key, value in schedule_metrics(schedule, dag, platform).items():
        schedule.metrics.setdefault(key, value)
    return schedule
