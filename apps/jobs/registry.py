"""Job kinds and their handlers.

A handler is ``handler(job, progress) -> (result: dict, result_url: str)``. ``progress(percent, message)``
records progress in the database. A handler must be idempotent: a job re-delivered after a worker died
runs again from the start and must replace, not duplicate, what a previous attempt stored.
Handlers raise :class:`~continuum.engine.core.errors.InputError` (or ``ValueError``) for bad arguments: the
job fails with that message and the worker carries on.
"""

from collections.abc import Callable
from typing import Any

Progress = Callable[[float, str], None]
Handler = Callable[[Any, Progress], tuple[dict, str]]

HANDLERS: dict[str, Handler] = {}


def job_kind(name: str) -> Callable[[Handler], Handler]:
    def register(fn: Handler) -> Handler:
        HANDLERS[name] = fn
        return fn

    return register
