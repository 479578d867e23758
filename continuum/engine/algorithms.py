"""The static DAG schedulers by name, so that commands, jobs and the API offer the same list."""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

from .dag import TaskGraph
from .errors import InputError
from .heft import Progress, heft
from .heft4k import heft4k
from .platform import Platform
from .schedule import Schedule

Scheduler = Callable[..., Schedule]

#: name -> function(dag, platform, **params) -> Schedule. Other modules register their methods here.
SCHEDULERS: dict[str, Scheduler] = {"heft": heft, "heft4k": heft4k}


def run(name: str, dag: TaskGraph, platform: Platform, progress: Progress | None = None, **params: Any) -> Schedule:
    """Schedule ``dag`` on ``platform`` with the algorithm called ``name``.

    ``progress(done, total)`` is passed on to the algorithms that report progress.
    """
    try:
        scheduler = SCHEDULERS[name]
    except KeyError:
        raise InputError(
            f"unknown algorithm {name!r} (choose from {', '.join(sorted(SCHEDULERS))})", "algorithm"
        ) from None
    if progress is not None and "progress" in inspect.signature(scheduler).parameters:
        params["progress"] = progress
    try:
        return scheduler(dag, platform, **params)
    except TypeError as exc:
        if "unexpected keyword" in str(exc):
            raise InputError(f"{name}: {exc}", "params") from exc
        raise
