"""Readers for the DAG formats Continuum accepts; :func:`load_dag` picks the right one.

Each reader turns a file into a validated :class:`~continuum.engine.core.dag.TaskGraph` or raises
:class:`~continuum.engine.core.errors.InputError` with a message naming the line or element at fault.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from pathlib import PurePath
from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import check_text_file, loads_json
from continuum.engine.formats import dax, stg, thesis_csv, wfformat

Reader = Callable[[Any], TaskGraph]

#: JSON readers by name; each takes the decoded document.
JSON_READERS: dict[str, Reader] = {
    "continuum": TaskGraph.from_dict,
    "wfformat": wfformat.read,
}
#: Text readers by name; each takes the file's text (and its own keyword options). Later formats register here.
TEXT_READERS: dict[str, Callable[..., TaskGraph]] = {
    "stg": stg.read,
    "dax": dax.read,
    "thesis_csv": thesis_csv.read,
}
#: File name endings -> format, for :func:`format_for_path`.
EXTENSIONS = {".stg": "stg", ".dax": "dax", ".xml": "dax", ".csv": "thesis_csv"}


def format_for_path(path: str) -> str | None:
    """The format a file name implies (``.stg``, ``.xml``/``.dax``, ``.csv``), or None (then: sniff)."""
    return EXTENSIONS.get(PurePath(path).suffix.lower())


def sniff_text(content: str) -> str | None:
    """Guess a text format from the content: XML -> dax, a lone integer first -> stg, commas -> thesis_csv."""
    head = content.lstrip()
    if head.startswith("<"):
        return "dax"
    if head.startswith(("{", "[")):
        return None  # JSON
    first = next((ln.strip() for ln in head.splitlines() if ln.strip()), "")
    if first.isdigit():
        return "stg"
    if "," in first:
        return "thesis_csv"
    return None


def sniff_json(doc: Any) -> str:
    if isinstance(doc, dict) and isinstance(doc.get("workflow"), dict):
        return "wfformat"
    return "continuum"


def load_dag(
    content: str | bytes, fmt: str | None = None, name: str | None = None, options: dict[str, Any] | None = None
) -> TaskGraph:
    """Parse ``content`` (the file's text) as ``fmt``, or guess the format when ``fmt`` is None.

    ``options`` go to the text reader (e.g. STG's ``ccr``, ``processors``, ``heterogeneity``, ``seed``).
    """
    if isinstance(content, bytes):
        try:
            content = content.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise InputError(f"the file is not UTF-8 text (byte {exc.start})") from exc
    check_text_file(content)
    if fmt is None:
        fmt = sniff_text(content)
    if fmt in TEXT_READERS:
        reader = TEXT_READERS[fmt]
        if options:
            accepted = inspect.signature(reader).parameters
            unknown = sorted(k for k in options if k not in accepted)
            if unknown:
                raise InputError(f"the {fmt} reader has no option {unknown[0]!r}", "format")
        graph = reader(content, **(options or {}))
    else:
        if options:
            raise InputError(f"the {fmt or 'JSON'} reader takes no options", "format")
        if fmt is not None and fmt not in JSON_READERS:
            known = ", ".join(sorted({*JSON_READERS, *TEXT_READERS}))
            raise InputError(f"unknown DAG format {fmt!r} (known: {known})", "format")
        doc = loads_json(content)
        graph = JSON_READERS[fmt or sniff_json(doc)](doc)
    if name:
        graph.name = name
    return graph
