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

from continuum.engine.core import limits
from continuum.engine.core.errors import InputError

__all__ = ["check_json_value", "check_text_file", "check_yaml_events", "load_yaml_all", "loads_json", "too_deep"]

# A JSON string (with escapes), matched whole so that brackets in it do not count (the unrolled form: one
# C-level scan per string rather than one alternation per character).
_STRING = re.compile(r'"[^"\\]*(?:\\.[^"\\]*)*"', re.DOTALL)
_NOT_BRACKET = bytes(sorted(set(range(256)) - set(b"[]{}")))
# What can hide a value loads_json refuses: a NUL escape, NaN/Infinity, a number that overflows a float (an
# exponent of 3+ digits after a digit, or 200+ digits in a row: with an exponent of at most 99 that stays below
# 1e308) or an integer of 300+ digits. Text without any of them needs no per-value hooks nor a walk (most
# documents; a string that looks like one, "x1e100", only sends its document the slow way). Found with
# substring searches over a copy whose digits read 0, exponent letters e and signs - (all in C).
_SHAPE = bytes(48 if 48 <= i <= 57 else 101 if i in b"eE" else 45 if i in b"+-" else 32 for i in range(256))
_SUSPECT = (b"0" * 200, b"0e000", b"0e-000")
#: A JSON escape of a UTF-16 surrogate: a lone one decodes to a string that UTF-8 (PostgreSQL, every response)
#: cannot encode. Pairs decode to one character and pass.
_SURROGATE_ESCAPE = re.compile(r"\\u[dD][89a-fA-F]")
_SURROGATE = re.compile("[\ud800-\udfff]")


def too_deep(text: str, limit: int) -> bool:
    """Whether JSON ``text`` nests objects/lists deeper than ``limit``, found without recursion."""
    if text.count("[") + text.count("{") <= limit:
        return False  # cannot be deeper than it has brackets
    # Strings removed by the regex engine, the other characters by bytes.translate, both in C: what is left
    # is the structure's brackets (a megabyte document leaves a few thousand), walked here.
    brackets = _STRING.sub("", text).encode("utf-8", "ignore").translate(None, _NOT_BRACKET)
    if brackets.count(b"[") + brackets.count(b"{") <= limit:
        return False
    depth = 0
    for c in brackets:
        if c in b"[{":
            depth += 1
            if depth > limit:
                return True
        else:
            depth -= 1
    return False


def _plain(text: str) -> bool:
    """Whether ``text`` surely holds no refused value (see ``_SUSPECT``); a false "no" only costs time."""
    if "\\u0000" in text or "NaN" in text or "Infinity" in text:
        return False
    shape = text.encode("utf-8", "surrogatepass").translate(_SHAPE)
    return not any(s in shape for s in _SUSPECT)


class _Bad:
    """A value JSON allows but Continuum refuses (NaN, Infinity, 1e400, a 400-digit integer): kept as a
    marker while parsing so that the error can name where it is."""

    def __init__(self, text: str, problem: str):
        self.text, self.problem = text, problem


def _constant(name: str) -> _Bad:
    return _Bad(name, f"{name} is not allowed: numbers must be finite")


def _float(text: str) -> float | _Bad:
    value = float(text)
    return value if math.isfinite(value) else _Bad(text, f"the number {text} is out of range: numbers must be finite")


def _int(text: str) -> int | _Bad:
    if len(text) > 300:  # also below Python's int-string conversion limit (4300 digits)
        return _Bad(text, f"the number {text[:20]}... has {len(text)} digits: too large")
    return int(text)


def _bad_text(s: str, surrogates: bool) -> bool:
    return "\x00" in s or (surrogates and _SURROGATE.search(s) is not None)


def _has_problem(doc: Any, surrogates: bool = False) -> bool:
    """Whether :func:`_first_problem` will find something: the same walk without building paths (fast)."""
    if surrogates:
        return _first_problem(doc, surrogates) is not None
    stack = [doc]
    pop, push = stack.pop, stack.extend
    while stack:
        node = pop()
        kind = type(node)
        if kind is dict:
            push(node.values())
            if any("\x00" in k for k in node):
                return True
        elif kind is list:
            push(node)
        elif kind is str:
            if "\x00" in node:
                return True
        elif kind is _Bad:
            return True
    return False


def _first_problem(doc: Any, surrogates: bool = False) -> tuple[str, str] | None:
    """(path, problem) of the first refused value: a marker, or a string (or key) holding a NUL (or, when
    ``surrogates``, a lone UTF-16 surrogate)."""
    stack: list[tuple[str, Any]] = [("", doc)]
    while stack:
        path, node = stack.pop()
        if isinstance(node, _Bad):
            return path, node.problem
        if isinstance(node, str) and _bad_text(node, surrogates):
            return path, _text_problem(node)
        if isinstance(node, dict):
            for key, value in reversed(list(node.items())):
                if _bad_text(key, surrogates):
                    return path, "a key " + _text_problem(key)
                stack.append((f"{path}.{key}" if path else key, value))
        elif isinstance(node, list):
            stack.extend((f"{path}[{i}]", v) for i, v in reversed(list(enumerate(node))))
    return None


def _text_problem(s: str) -> str:
    if "\x00" in s:
        return "contains a NUL character, which no text may hold"
    return "contains a lone UTF-16 surrogate (\\ud800-\\udfff), which is not text"


def check_text_file(text: str) -> None:
    """An uploaded text file may hold no NUL: no text format has one, and no stored text may hold one
    (PostgreSQL's text and jsonb refuse it)."""
    if "\x00" in text:
        raise InputError("the file contains a NUL character")


def loads_json(text: str | bytes, field: str | None = None, *, max_depth: int | None = None) -> Any:
    """``json.loads`` for untrusted text; every problem is an InputError on ``field`` (or, without one, on
    the document's top-level key where the problem is), naming the path, e.g. ``meta.x: NaN is not
    allowed``."""
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise InputError(f"not UTF-8 text (byte {exc.start})", field) from exc
    limit = max_depth if max_depth is not None else limits.get().json_depth
    if too_deep(text, limit):
        raise InputError(f"nested too deeply: at most {limit} levels of objects and lists", field)
    plain = _plain(text)
    try:
        if plain:
            doc = json.loads(text)
        else:
            doc = json.loads(text, parse_constant=_constant, parse_float=_float, parse_int=_int)
    except json.JSONDecodeError as exc:
        raise InputError(f"malformed JSON at line {exc.lineno} column {exc.colno}: {exc.msg}", field) from exc
    except RecursionError as exc:  # not expected after the depth scan; never a 500 all the same
        raise InputError("nested too deeply", field) from exc
    surrogates = _SURROGATE_ESCAPE.search(text) is not None  # only escapes make them: text is decoded UTF-8
    if plain and not surrogates:
        return doc
    found = _first_problem(doc, surrogates) if _has_problem(doc, surrogates) else None  # iterative, linear
    if found is not None:
        path, problem = found
        top = re.split(r"[.\[]", path, maxsplit=1)[0] if path else None
        raise InputError(f"{path}: {problem}" if path else problem, field or top or None)
    return doc


def check_yaml_events(text: str, field: str | None = None, *, max_depth: int | None = None) -> None:
    """Depth, aliases and NUL of a YAML stream, checked on the events of PyYAML's pure-Python parser (a state
    machine with its own stack: no recursion) before any loader builds nodes. The composers recurse once per
    level, and libyaml's C one (``CSafeLoader``) overflows the C stack and kills the process on about 60 KB
    of ``[`` (issue 25); run this first on any text a loader will see. YAMLError for malformed text."""
    lim = limits.get()
    limit = max_depth if max_depth is not None else lim.json_depth
    if "\x00" in text:
        raise InputError("contains a NUL character, which no text field may hold", field)
    depth = aliases = 0
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


def load_yaml_all(text: str, field: str | None = None, *, max_depth: int | None = None) -> list[Any]:
    """Every document of a YAML stream, after an iterative check of depth, aliases and NUL."""
    try:
        check_yaml_events(text, field, max_depth=max_depth)
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
