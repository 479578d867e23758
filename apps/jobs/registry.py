"""Job kinds and their handlers: a typed registry.

Each app declares its job kinds as a :class:`JobKind` (a ``StrEnum``) in its ``kinds.py``, and the app that
runs a kind registers its handler with ``@job_kind(SomeKinds.MEMBER)``. Callers start jobs with the member
(``start_job(SchedulingJob.SCHEDULE, ...)``), never with a bare string, so every use of a kind is found by
its name and a typo is an ``AttributeError`` at import time. The member's value is what ``Job.kind`` stores
(rows and API output keep their strings).

A handler is ``handler(job, progress) -> (result: dict, result_url: str)``. ``progress(percent, message)``
records progress in the database. A handler must be idempotent: a job re-delivered after a worker died
runs again from the start and must replace, not duplicate, what a previous attempt stored.
Handlers raise :class:`~continuum.engine.core.errors.InputError` (or ``ValueError``) for bad arguments: the
job fails with that message and the worker carries on.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import StrEnum
from typing import Any

Progress = Callable[[float, str], None]
Handler = Callable[[Any, Progress], tuple[dict, str]]


class JobKind(StrEnum):
    """The base of every app's job kinds: ``class SchedulingJob(JobKind): SCHEDULE = "schedule"``."""


class UnknownJobKind(ValueError):
    """A job kind that no app registered a handler for."""


#: Handler per kind, keyed by the kind's stored string (``Job.kind``).
HANDLERS: dict[str, Handler] = {}
#: The registered kinds, by their stored string.
KINDS: dict[str, JobKind] = {}


def job_kind(kind: JobKind) -> Callable[[Handler], Handler]:
    """Register ``fn`` as the handler of ``kind`` (a :class:`JobKind` member; a bare string is refused)."""
    if not isinstance(kind, JobKind):
        raise TypeError(f"job kinds are JobKind members (declared in an app's kinds.py), not {kind!r}")

    def register(fn: Handler) -> Handler:
        existing = HANDLERS.get(kind.value)
        if existing is not None and _name(existing) != _name(fn):
            raise ValueError(f"job kind {kind.value!r} already has a handler, {_name(existing)}")
        HANDLERS[kind.value] = fn
        KINDS[kind.value] = kind
        return fn

    return register


def resolve(kind: JobKind | str) -> str:
    """The stored string of a registered kind; :class:`UnknownJobKind` for any other."""
    value = kind.value if isinstance(kind, JobKind) else kind
    if not isinstance(value, str) or value not in HANDLERS:
        known = ", ".join(sorted(HANDLERS)) or "none"
        raise UnknownJobKind(f"unknown job kind {value!r}: no app registered a handler for it (registered: {known})")
    return value


def id_argument(job: Any, name: str, *, required: bool = True, what: str | None = None) -> int | None:
    """The row id stored in ``job.arguments[name]`` (stored JSON, so checked again here); ``ValueError`` naming
    the argument when it is not an integer, or missing while ``required``. ``what`` names the row's type in
    the message (default: ``name``)."""
    value = (job.arguments or {}).get(name)
    if value is None and not required:
        return None
    if not isinstance(value, int) or isinstance(value, bool):
        raise ValueError(f"argument {name!r} must be the id of a {what or name}, got {value!r}")
    return value


def owned_row(job: Any, rows: Any, name: str, *, what: str | None = None, required: bool = True) -> Any:
    """The row of ``rows`` (a manager or queryset) whose id is ``job.arguments[name]``, among the job's fleet's:
    a job only ever touches its own fleet's rows. ``ValueError`` "<what> <id> does not exist" when there is
    none; ``None`` when the argument is absent and not ``required``."""
    pk = id_argument(job, name, required=required)
    if pk is None:
        return None
    row = rows.filter(pk=pk, fleet=job.fleet).first()
    if row is None:
        raise ValueError(f"{what or name} {pk} does not exist")
    return row


def _name(fn: Callable) -> str:
    return f"{getattr(fn, '__module__', '?')}.{getattr(fn, '__qualname__', repr(fn))}"


#: What each kind does, in words, for the job pages (registered with the kinds, in the apps' kinds.py).
TITLES: dict[str, str] = {}


def describe_kinds(titles: dict[JobKind, str]) -> None:
    """Register what each kind of ``titles`` does, in words ("Schedule an application's DAG")."""
    for kind, title in titles.items():
        if not isinstance(kind, JobKind):
            raise TypeError(f"job kinds are JobKind members, not {kind!r}")
        TITLES[kind.value] = title


def kind_title(kind: str) -> str:
    """The registered words for ``kind``; else the kind's name made readable ("push_schedule": "Push schedule")."""
    return TITLES.get(kind) or kind.replace("_", " ").capitalize()
