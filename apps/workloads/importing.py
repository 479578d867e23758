"""Reading an uploaded DAG file and generating a synthetic DAG: the glue the API and the dashboard share.

The format comes from the caller (by name), else from the file name (``.stg``, ``.dax``/``.xml``,
``.csv``), else from the content (:func:`continuum.engine.formats.load_dag` sniffs it). Reader options
(STG's ``ccr``, ``processors``, ``heterogeneity``, ``seed``, ``dummies``) go to the text readers; a bad
option is an :class:`InputError` on the field ``options``, a bad file one on ``file``.
"""

from __future__ import annotations

from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import loads_json
from continuum.engine.device import generators
from continuum.engine.formats import JSON_READERS, TEXT_READERS, format_for_path, load_dag

FORMATS = sorted({*JSON_READERS, *TEXT_READERS})
GENERATORS = ("thesis", "layered")


def parse_options(value: Any) -> dict[str, Any]:
    """Reader options: a JSON object (or its text) of numbers and booleans; empty means none."""
    if value in (None, ""):
        return {}
    if isinstance(value, (str, bytes)):
        try:
            value = loads_json(value, "options")
        except InputError as exc:
            message = str(exc)
            message = f"not JSON ({message})" if message.startswith("malformed") else message
            raise InputError(message, "options") from exc
    if not isinstance(value, dict):
        raise InputError('reader options must be a JSON object, e.g. {"ccr": 1}', "options")
    for key, v in value.items():
        if not isinstance(v, (int, float, bool)):
            raise InputError(f"reader option {key!r} must be a number or true/false, not {v!r}", "options")
    return value


def read_dag_file(
    content: bytes | str,
    filename: str,
    fmt: str | None = None,
    options: dict[str, Any] | None = None,
    name: str | None = None,
) -> tuple[TaskGraph, str]:
    """(the DAG, the format it was read as) from an uploaded file; see the module docstring."""
    fmt = fmt or format_for_path(filename)
    try:
        graph = load_dag(content, fmt, name=name, options=options or None)
    except InputError as exc:
        # load_dag names the field "format" for an option the reader does not take.
        field = "options" if options and exc.field == "format" else "file"
        raise InputError(str(exc) if field == "options" else f"{filename}: {exc}", field) from exc
    except (TypeError, ValueError) as exc:  # an option value of the wrong kind deep in a reader
        raise InputError(f"a reader option has a value the {fmt} reader cannot use: {exc}", "options") from exc
    return graph, fmt or graph.meta.get("source_format", "continuum")


def generate_dag(generator: str, **params: Any) -> TaskGraph:
    """A seeded synthetic DAG: ``thesis`` (spec 01 section 8.2, Tree/Linear) or ``layered`` (Topcuoglu et al.)."""
    params = {k: v for k, v in params.items() if v is not None}
    if generator == "thesis":
        seed = params.pop("seed", 0)
        if "shape" in params:
            raise InputError("shape is the layered generator's; the thesis generator takes dag_class", "shape")
        if "dag_class" in params:
            params["shape"] = params.pop("dag_class")
        allowed = {"n", "shape"}
        return _call(generators.thesis_dag, seed, allowed, params)
    if generator == "layered":
        n = params.pop("n", 100)
        if "dag_class" in params:
            raise InputError("dag_class (tree or linear) is the thesis generator's", "dag_class")
        allowed = {"seed", "shape", "out_degree", "ccr", "mean_cost", "processors", "heterogeneity"}
        return _call(generators.layered_dag, n, allowed, params)
    raise InputError(f"unknown generator {generator!r} (choose from {', '.join(GENERATORS)})", "generator")


def _call(fn, first: Any, allowed: set[str], params: dict[str, Any]) -> TaskGraph:
    unknown = sorted(set(params) - allowed)
    if unknown:
        raise InputError(f"{fn.__name__} takes no parameter {unknown[0]!r}", unknown[0])
    return fn(first, **params)
