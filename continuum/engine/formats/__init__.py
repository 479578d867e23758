"""Readers for the DAG formats Continuum accepts; :func:`load_dag` picks the right one.

Each reader turns a file into a validated :class:`~continuum.engine.dag.TaskGraph` or raises
:class:`~continuum.engine.errors.InputError` with a message naming the line or element at fault.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

from ..dag import TaskGraph
from ..errors import InputError
from . import wfformat

Reader = Callable[[Any], TaskGraph]

#: JSON readers by name; each takes the decoded document.
JSON_READERS: dict[str, Reader] = {
    "continuum": TaskGraph.from_dict,
    "wfformat": wfformat.read,
}
#: Text readers by name; each takes the file's text. Later formats register here.
TEXT_READERS: dict[str, Callable[[str], TaskGraph]] = {}


def sniff_json(doc: Any) -> str:
    if isinstance(doc, dict) and isinstance(doc.get("workflow"), dict):
        return "wfformat"
    return "continuum"


def load_dag(content: str | bytes, fmt: str | None = None, name: str | None = None) -> TaskGraph:
    """Parse ``content`` (the file's text) as ``fmt``, or guess the format when ``fmt`` is None."""
    if isinstance(content, bytes):
        try:
            content = content.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise InputError(f"the file is not UTF-8 text (byte {exc.start})") from exc
    if fmt in TEXT_READERS:
        graph = TEXT_READERS[fmt](content)
    else:
        if fmt is not None and fmt not in JSON_READERS:
            known = ", ".join(sorted({*JSON_READERS, *TEXT_READERS}))
            raise InputError(f"unknown DAG format {fmt!r} (known: {known})", "format")
        try:
            doc = json.loads(content)
        except json.JSONDecodeError as exc:
            raise InputError(f"malformed JSON at line {exc.lineno} column {exc.colno}: {exc.msg}") from exc
        graph = JSON_READERS[fmt or sniff_json(doc)](doc)
    if name:
        graph.name = name
    return graph
