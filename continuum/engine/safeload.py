"""Reading JSON and YAML from strangers: depth, aliases, NaN/Infinity and NUL are checked *before* any
recursive code runs, so a hostile document is an :class:`InputError`, never a RecursionError or a stored
value the database cannot hold.

* JSON: the structural characters are scanned iteratively (strings skipped) and a document nested deeper
  than ``limits.json_depth`` is rejected before :func:`json.loads` recurses into it; ``NaN``, ``Infinity``
  and numbers that overflow to infinity (``1e400``) are rejected (PostgreSQL's jsonb holds neither, and no
  Continuum field means them); so is a NUL character in any string (PostgreSQL text holds none).
* YAML: the event stream (:func:`yaml.parse`, iterative) is walked first: depth above the limit, more
  than ``limits.yaml_aliases`` aliases (the "billion laughs" bomb) or a NUL is rejected before anything
  is composed; then ``yaml.safe_load_all`` builds the documents.
"""

from __future__ import annotations

import json
import math
import re
from typing import Any

import yaml

from . import limits
from .errors import InputError

# A JSON string (with escapes) or one structural bracket; strings are matched whole so brackets in them
# do not count.
_TOKENS = re.compile(r'"(?:[^"\\]|\\.)*"|[\[\]{}]', re.DOTALL)


def too_deep(text: str, limit: int) -> bool:
    """Whether JSON ``text`` nests objects/lists deeper than ``limit``, found without recursion."""
    if text.count("[") + text.count("{") <= limit:
        return False  # cannot be deeper than it has brackets
    depth = 0
    for m in _TOKENS.finditer(text):
        c = m.group()
        if c in "[{":
            depth += 1
            if depth > limit:
                return True
        elif c in "]}":
            depth -= 1
    return False


def _reject_constant(name: str) -> Any:
    raise InputError(f"{name} is not allowed: numbers must be finite")


def _finite_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise InputError(f"the number {text} is out of range: numbers must be finite")
    return value


def _finite_int(text: str) -> int:
    if len(text) > 300:  # also below Python's int-string conversion limit (4300 digits)
        raise InputError(f"the number {text[:20]}... has {len(text)} digits: too large")
    return int(text)


def loads_json(text: str | bytes, field: str | None = None, *, max_depth: int | None = None) -> Any:
    """``json.loads`` for untrusted text; every problem is an InputError on ``field``."""
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise InputError(f"not UTF-8 text (byte {exc.start})", field) from exc
    limit = max_depth if max_depth is not None else limits.get().json_depth
    if too_deep(text, limit):
        raise InputError(f"nested too deeply: at most {limit} levels of objects and lists", field)
    if "\x00" in text or "\\u0000" in text:
        raise InputError("contains a NUL character, which no text field may hold", field)
    try:
        return json.loads(
            text, parse_constant=_reject_constant, parse_float=_finite_float, parse_int=_finite_int
        )
    except InputError as exc:
        raise InputError(str(exc), field) from None
    except json.JSONDecodeError as exc:
        raise InputError(f"malformed JSON at line {exc.lineno} column {exc.colno}: {exc.msg}", field) from exc
    except RecursionError as exc:  # not expected after the depth scan; never a 500 all the same
        raise InputError("nested too deeply", field) from exc


def load_yaml_all(text: str, field: str | None = None, *, max_depth: int | None = None) -> list[Any]:
    """Every document of a YAML stream, after an iterative check of depth, aliases and NUL."""
    lim = limits.get()
    limit = max_depth if max_depth is not None else lim.json_depth
    if "\x00" in text:
        raise InputError("contains a NUL character, which no text field may hold", field)
    depth = aliases = 0
    try:
        for event in yaml.parse(text, Loader=yaml.SafeLoader):
            if isinstance(event, (yaml.MappingStartEvent, yaml.SequenceStartEvent)):
                depth += 1
                if depth > limit:
                    raise InputError(f"nested too deeply: at most {limit} levels of mappings and lists", field)
            elif isinstance(event, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
                depth -= 1
            elif isinstance(event, yaml.AliasEvent):
                aliases += 1
                if aliases > lim.yaml_aliases:
                    raise InputError(f"too many YAML aliases: at most {lim.yaml_aliases}", field)
        docs = list(yaml.safe_load_all(text))
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1} column {mark.column + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc)
        raise InputError(f"malformed YAML{where}: {problem}", field) from exc
    except RecursionError as exc:
        raise InputError("nested too deeply", field) from exc
    for doc in docs:
        _check_finite(doc, field)
    return docs


def _check_finite(doc: Any, field: str | None) -> None:
    """YAML's ``.nan``/``.inf`` become floats; reject them like JSON's NaN (iteratively: depth is bounded
    but aliases may share subtrees)."""
    stack, seen = [doc], set()
    while stack:
        node = stack.pop()
        if isinstance(node, float) and not math.isfinite(node):
            raise InputError(f"{node} is not allowed: numbers must be finite", field)
        if isinstance(node, (dict, list)):
            if id(node) in seen:
                continue
            seen.add(id(node))
            stack.extend(node.values() if isinstance(node, dict) else node)
            if isinstance(node, dict):
                stack.extend(k for k in node if isinstance(k, float))


def check_json_value(value: Any, field: str | None = None, *, max_depth: int | None = None) -> None:
    """Check an already-decoded value (e.g. from a form) the way :func:`loads_json` checks text:
    depth, finite numbers, no NUL in strings. Iterative."""
    limit = max_depth if max_depth is not None else limits.get().json_depth
    stack: list[tuple[Any, int]] = [(value, 0)]
    while stack:
        node, depth = stack.pop()
        if isinstance(node, float) and not math.isfinite(node):
            raise InputError(f"{node} is not allowed: numbers must be finite", field)
        if isinstance(node, str) and "\x00" in node:
            raise InputError("contains a NUL character, which no text field may hold", field)
        if isinstance(node, (dict, list)):
            if depth + 1 > limit:
                raise InputError(f"nested too deeply: at most {limit} levels of objects and lists", field)
            items = list(node.items()) if isinstance(node, dict) else [(None, v) for v in node]
            for k, v in items:
                if isinstance(k, str) and "\x00" in k:
                    raise InputError("contains a NUL character, which no text field may hold", field)
                stack.append((v, depth + 1))
