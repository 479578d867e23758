"""``loads_json``'s fast path (issue 29): plain documents skip the per-value hooks and the walk, and every
refused value still sends its document the checked way (same errors as before)."""

import json

import pytest

from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import loads_json, too_deep


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('{"a": NaN}', "a: NaN is not allowed"),
        ('{"a": [1, Infinity]}', r"a\[1\]: Infinity is not allowed"),
        ('{"a": 1e400}', "out of range"),
        ('{"a": 1.5E+400}', "out of range"),
        ('{"a": ' + "9" * 250 + ".0e99}", "out of range"),
        ('{"a": ' + "9" * 301 + "}", "digits: too large"),
        ('{"a\\u0000": 1}', "a key contains a NUL"),
        ('{"a": "x\\u0000"}', "a: contains a NUL"),
    ],
)
def test_refused_values_are_still_refused(text, message):
    with pytest.raises(InputError, match=message):
        loads_json(text)


def test_plain_documents_parse_as_json_does():
    # Strings that look like exponents or overflow ("node-00123", "x1e100") change nothing but the path taken.
    doc = {"node-00123": 1.25, "x1e100": "e-001", "n": [1, 2.5e-3, -7, 1e99], "deep": [[[{"k": None}]]]}
    text = json.dumps(doc)
    assert loads_json(text) == doc


def test_depth_counts_brackets_outside_strings_only():
    assert too_deep("[" * 70 + "]" * 70, 64)
    assert not too_deep("[" * 64 + "]" * 64, 64)
    assert not too_deep(json.dumps({"s": "[" * 500, "t": [{"u": "{" * 100}] * 80}), 64)
    assert too_deep(json.dumps({"s": '"\\"[', "x": [[[[1]]]]}).replace("[[[[1]]]]", "[" * 65 + "]" * 65), 64)
    with pytest.raises(InputError, match="nested too deeply"):
        loads_json("[" * 100 + "]" * 100)
