"""Hypothesis strategies that mutate a real sample document: one value, key or line at a time.

A JSON document is mutated at one path (numbers -> huge/NaN/inf/negative/-1/1e400, strings -> NUL/huge/
HTML, types swapped, lists nested, deep nesting, keys dropped or duplicated). Mutations JSON cannot express
as a Python value (NaN, 1e400, a duplicated key, 100k-deep nesting) are spliced into the text at a
placeholder. A text document (STG, DAX, CSV, DOT, YAML, an assertion) is mutated at one line or token.
"""

from __future__ import annotations

import json
from typing import Any

from hypothesis import strategies as st

PLACEHOLDER = "__fuzz_placeholder__"

#: Raw JSON texts spliced in place of a value.
RAW_VALUES = ["NaN", "Infinity", "-Infinity", "1e400", "-1e400", "1" + "0" * 400, "[" * 5000 + "]" * 5000]
#: Python values put in place of a value.
VALUES: list[Any] = [
    1e300, -1e300, 1e20, -1, 0, -0.5, 2**63, -(2**63), 10**30, 1e-300,
    "", "\x00", "a\x00b", "x" * 100_000, "<script>alert(1)</script>", "\u202e\ufeff", "1e400", "NaN", "-1",
    None, True, False, [], {}, [[[[1]]]], {"a": {"b": {"c": []}}}, [None], ["x"] * 10_000,
]  # fmt: skip


def _paths(doc: Any) -> list[tuple]:
    """Every path (tuple of keys/indexes) in ``doc``, iteratively; big lists are sampled at a few indexes."""
    out: list[tuple] = [()]
    stack: list[tuple[tuple, Any]] = [((), doc)]
    while stack:
        path, node = stack.pop()
        if isinstance(node, dict):
            items = list(node.items())
        elif isinstance(node, list):
            idx = sorted({0, 1, len(node) // 2, len(node) - 1} & set(range(len(node))))
            items = [(i, node[i]) for i in idx]
        else:
            continue
        for k, v in items:
            out.append((*path, k))
            stack.append(((*path, k), v))
    return out


def _get(doc: Any, path: tuple) -> Any:
    for k in path:
        doc = doc[k]
    return doc


def _set(doc: Any, path: tuple, value: Any) -> Any:
    if not path:
        return value
    _get(doc, path[:-1])[path[-1]] = value
    return doc


@st.composite
def mutated_json(draw, doc: Any) -> str:
    """The text of ``doc`` with one mutation."""
    doc = json.loads(json.dumps(doc))
    paths = _paths(doc)
    path = draw(st.sampled_from(paths))
    target = _get(doc, path)
    kind = draw(st.sampled_from(["value", "raw", "swap", "nest", "drop", "dup", "deep"]))
    raw = None
    if kind == "value":
        doc = _set(doc, path, draw(st.sampled_from(VALUES)))
    elif kind == "raw":
        doc, raw = _set(doc, path, PLACEHOLDER), draw(st.sampled_from(RAW_VALUES))
    elif kind == "swap":  # the same content as another type
        swapped = {
            int: str, float: str, str: lambda s: len(s), bool: str, type(None): lambda _: "null",
            list: lambda v: dict(enumerate(v)), dict: lambda v: list(v.values()),
        }[type(target)](target)  # fmt: skip
        doc = _set(doc, path, json.loads(json.dumps(swapped, default=str)))
    elif kind == "nest":
        doc = _set(doc, path, [target] if not isinstance(target, list) else [[v] for v in target])
    elif kind == "drop" and path:
        parent = _get(doc, path[:-1])
        del parent[path[-1]]
    elif kind == "dup" and isinstance(target, dict) and target:
        key = next(iter(target))
        inner = json.dumps(target)[1:-1]
        doc = _set(doc, path, PLACEHOLDER)
        raw = "{" + json.dumps(key) + ": " + json.dumps(draw(st.sampled_from(VALUES[:20]))) + ", " + inner + "}"
    elif kind == "deep":
        depth = draw(st.sampled_from([65, 1000, 100_000]))
        doc, raw = _set(doc, path, PLACEHOLDER), "[" * depth + "]" * depth
    text = json.dumps(doc)
    if raw is not None:
        text = text.replace(json.dumps(PLACEHOLDER), raw, 1)
    return text


TEXT_TOKENS = [
    "-1", "0", "1e400", "1e300", "NaN", "inf", "-inf", "99999999999999999999999", "\x00", "<x>", "&amp;", "\"",
    ",", ";", "{", "[", "(", "]]]]", "x" * 5000, "!" * 3000, "(" * 3000, "&&" * 2000, "\t", "\r\n", "", " ",
]  # fmt: skip


@st.composite
def mutated_text(draw, text: str) -> str:
    """``text`` with one line dropped, duplicated, or one token replaced or inserted."""
    lines = text.splitlines(keepends=True) or [""]
    i = draw(st.integers(0, len(lines) - 1))
    kind = draw(st.sampled_from(["drop", "dup", "replace", "insert", "truncate"]))
    if kind == "drop":
        del lines[i]
    elif kind == "dup":
        lines.insert(i, lines[i])
    elif kind == "truncate":
        return text[: draw(st.integers(0, max(0, len(text) - 1)))]
    else:
        line = lines[i]
        tokens = line.replace(",", " , ").split(" ")
        j = draw(st.integers(0, max(0, len(tokens) - 1)))
        token = draw(st.sampled_from(TEXT_TOKENS))
        if kind == "replace" and tokens:
            tokens[j] = token
        else:
            tokens.insert(j, token)
        lines[i] = " ".join(tokens).replace(" , ", ",")
    return "".join(lines)
