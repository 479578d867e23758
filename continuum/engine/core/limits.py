"""The maxima of every input that drives cost, in one place (README, "Limits").

The API, the dashboard forms, the management commands and the engine's readers all read :func:`get`; none
keeps its own copy of a number. Each maximum can be overridden by an environment variable
``CONTINUUM_MAX_<NAME>`` (e.g. ``CONTINUUM_MAX_FRAMES=2000``), read once when the module is imported;
:func:`override` replaces them for a block (tests).

Breaking a limit is an :class:`~continuum.engine.core.errors.InputError` naming the field and the maximum, e.g.
``frames: at most 1000`` (:func:`check`).
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from continuum.engine.core.errors import InputError

__all__ = ["Limits", "check", "get", "override"]


@dataclass(frozen=True)
class Limits:
    """Maxima; every one is documented in the README's table."""

    #: Frames one schedule request may pipeline (and the largest ``batch``).
    frames: int = 1000
    #: Frames x tasks of one pipelined schedule (every frame's tasks are placed and kept in memory).
    frame_tasks: int = 1_000_000
    #: Tasks of one DAG (imported, generated or built from a ROS graph).
    tasks: int = 20_000
    #: Edges of one DAG.
    edges: int = 200_000
    #: Task cost entries of one DAG (tasks x processor classes); bounds ``n x processors`` of the generators.
    cost_entries: int = 1_000_000
    #: The layered generator's mean out-degree.
    out_degree: float = 100.0
    #: Processors of one platform document or generated cost table.
    processors: int = 1024
    #: CPU cores of one processor or cluster node (a node's ``cpu``).
    cores: int = 1024
    #: Nodes of one cluster document (``continuum.cluster/v1``, RT sets) and of one ROS graph.
    nodes: int = 5000
    #: Links of one cluster document and edges of one ROS graph.
    links: int = 50_000
    #: Bytes of one uploaded file, and of the request body of an endpoint that takes a document or a file.
    upload_bytes: int = 32 * 1024 * 1024
    #: Bytes of the request body of every other API endpoint (a form of fields, an action's few options).
    body_bytes: int = 1024 * 1024
    #: Nesting depth of a JSON or YAML document (objects and lists).
    json_depth: int = 64
    #: YAML aliases (``*name``) in one document: blocks "billion laughs" alias bombs.
    yaml_aliases: int = 100
    #: Nesting depth of one assertion (parentheses, ``!``, ``F``/``X``, operator chains).
    stl_depth: int = 50
    #: Characters of one assertion.
    stl_length: int = 10_000
    #: The most rows one list page returns (``?limit=``).
    page_size: int = 1000
    #: Publishing rate of one ROS topic or publisher, in Hz (``rate_hz``).
    rate_hz: float = 100_000.0
    #: Size of one ROS message, in bytes (``msg_bytes``): 1 GiB.
    msg_bytes: int = 1 << 30
    #: Memory of one ROS node's profile, in MiB (``memory_mib``): 1 TiB.
    memory_mib: int = 1 << 20
    #: Largest task cost, edge data size, latency or other figure of a DAG, platform or cluster document. With
    #: ``min_rate`` it keeps every sum a scheduler makes finite: (tasks + edges) x frames x magnitude / min_rate
    #: is about 2e26 at the other maxima, where 1e308 costs overflowed to inf and NaN inside jobs (issue 25).
    magnitude: float = 1e12
    #: Smallest processor speed factor or link bandwidth (a cost or data size is divided by it).
    min_rate: float = 1e-6

    @classmethod
    def from_env(cls, environ: Mapping[str, str] | None = None) -> Limits:
        """The defaults with ``CONTINUUM_MAX_<NAME>`` overrides; a malformed override is a start-up error."""
        environ = os.environ if environ is None else environ
        values: dict[str, Any] = {}
        for f in dataclasses.fields(cls):
            raw = environ.get(f"CONTINUUM_MAX_{f.name.upper()}")
            if raw is None or raw.strip() == "":
                continue
            kind = float if f.type in ("float", float) else int
            try:
                value = kind(raw)
            except ValueError as exc:
                raise ValueError(f"CONTINUUM_MAX_{f.name.upper()}={raw!r} is not a number") from exc
            if not (isinstance(value, int) or math.isfinite(value)) or value <= 0:
                raise ValueError(f"CONTINUUM_MAX_{f.name.upper()} must be a positive number")
            values[f.name] = value
        return cls(**values)

    def as_dict(self) -> dict[str, float]:
        return dataclasses.asdict(self)


_current = Limits.from_env()


def get() -> Limits:
    """The limits in force."""
    return _current


@contextmanager
def override(**changes: Any) -> Iterator[Limits]:
    """Replace some maxima inside a ``with`` block (tests)."""
    global _current
    saved = _current
    _current = dataclasses.replace(saved, **changes)
    try:
        yield _current
    finally:
        _current = saved


def check(field: str, value: float, maximum: float | None = None, *, name: str | None = None) -> None:
    """Raise ``InputError("<field>: at most <max>")`` when ``value`` exceeds the limit ``name`` (default:
    ``field``) or the explicit ``maximum``."""
    limit = maximum if maximum is not None else getattr(_current, name or field)
    if value > limit:
        raise InputError(f"{field}: at most {_fmt(limit)} (got {_fmt(value)})", field)


def _fmt(v: float) -> str:
    if isinstance(v, float) and not math.isfinite(v):
        return str(v)
    if isinstance(v, float) and v.is_integer() and abs(v) < 1e15:
        v = int(v)
    if isinstance(v, int) and abs(v) >= 10_000:
        return f"{v:,}"
    return f"{v:g}" if isinstance(v, float) else str(v)
