"""The rtset reader's WCET check (issue 29): all values at once when they are fine, the first bad one named
otherwise, exactly as the value-by-value check names it."""

import math

import pytest

from continuum.engine.core.errors import InputError
from continuum.engine.rtkube.rt_model import rtset_from_dict


def doc(wcet):
    return {"containers": [{"name": "c", "criticality": "A", "period": 10, "deadline": 8, "wcet": wcet}]}


def test_good_wcets_read_as_floats():
    [c] = rtset_from_dict(doc({"n1": 1, "n2": 2.5, "n3": 8}), ["n1", "n2", "n3", "n4"])
    assert c.wcet == {"n1": 1.0, "n2": 2.5, "n3": 8.0} and all(type(v) is float for v in c.wcet.values())


@pytest.mark.parametrize(
    ("wcet", "message"),
    [
        ({"n1": 1, "n2": True}, "wcet on node 'n2' must be a finite number, got True"),
        ({"n1": "1"}, "must be a finite number"),
        ({"n1": 1, "n2": math.nan}, "must be a finite number"),
        ({"n1": 1, "n2": math.inf}, "must be a finite number"),
        ({"n1": 0}, "must be positive"),
        ({"n1": 1, "n2": -2}, "wcet on node 'n2' must be positive"),
        ({"n1": 9, "n2": 10}, "wcet 9 on node 'n1' exceeds deadline 8"),
        ({"n1": 1, "mars": 1}, "wcet names unknown node 'mars'"),
    ],
)
def test_bad_wcets_name_the_first_bad_value(wcet, message):
    with pytest.raises(InputError, match=message):
        rtset_from_dict(doc(wcet), ["n1", "n2"])
