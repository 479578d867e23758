"""The static DAG schedulers by name, so that commands, jobs and the API offer the same list.

The device-level methods are listed here; a method of a later chapter registers itself with :func:`register`
when its module is imported (HEFT4K does, :mod:`continuum.engine.heft4k.heft4k`), so this module never imports
the chapters above it. ``continuum.engine`` imports those modules, so the list is complete as soon as any
engine module is imported.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

from continuum.engine.core.errors import InputError
from continuum.engine.core.schedule import Schedule
from continuum.engine.device.gfl import gfl, gfl_c
from continuum.engine.device.heft import Progress, heft
from continuum.engine.device.visionworks import visionworks, visionworks_overlap
from continuum.engine.device.xeft import xeft

__all__ = ["ORDER", "SCHEDULERS", "Scheduler", "call", "register", "unknown"]

Scheduler = Callable[..., Schedule]

#: The order in which the methods are listed (forms, comparisons); registered methods not named here follow.
ORDER = ("heft", "heft4k", "xeft", "gfl", "gfl_c", "visionworks", "visionworks_overlap")

#: name -> function(dag, platform, **params) -> Schedule. Other modules register their methods with :func:`register`.
SCHEDULERS: dict[str, Scheduler] = {
    "heft": heft,
    "xeft": xeft,
    "gfl": gfl,
    "gfl_c": gfl_c,
    "visionworks": visionworks,
    "visionworks_overlap": visionworks_overlap,
}


def register(name: str, fn: Scheduler) -> Scheduler:
    """Offer ``fn`` as the scheduler called ``name`` (kept in :data:`ORDER`); returns ``fn``."""
    SCHEDULERS[name] = fn
    rank = {n: i for i, n in enumerate(ORDER)}
    ordered = sorted(SCHEDULERS.items(), key=lambda item: rank.get(item[0], len(ORDER)))
    SCHEDULERS.clear()
    SCHEDULERS.update(ordered)
    return fn


def unknown(name: str, field: str = "algorithm") -> InputError:
    """The error for a scheduler name that is not registered."""
    return InputError(f"unknown algorithm {name!r} (choose from {', '.join(sorted(SCHEDULERS))})", field)


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
