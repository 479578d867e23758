"""PlacementPlan.to_dict / from_dict: the stored plan reads back as the same plan (issue 11)."""

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from continuum.engine.core.placement import Decision, NodeVerdict, PlacementPlan

names = st.text(st.characters(codec="utf-8", exclude_categories=("Cs",)), min_size=1, max_size=8)
numbers = st.floats(allow_nan=False, allow_infinity=False, width=64)
verdicts = st.builds(
    NodeVerdict,
    node=names,
    rejected_by=st.none() | names,
    reason=st.text(max_size=20),
    scores=st.dictionaries(names, numbers, max_size=3),
    total=st.none() | numbers,
)
decisions = st.builds(
    Decision,
    item=names,
    node=st.none() | names,
    score=st.none() | numbers,
    verdicts=st.lists(verdicts, max_size=3).map(tuple),
)
reserved = {"policy", "placements", "pending", "decisions", "params", "explain"}
plans = st.builds(
    PlacementPlan,
    policy=names,
    decisions=st.lists(decisions, max_size=4),
    params=st.dictionaries(names, st.integers() | names | st.booleans(), max_size=3),
    metrics=st.dictionaries(names.filter(lambda k: k not in reserved), st.integers() | numbers, max_size=3),
)


@settings(max_examples=200, deadline=None)
@given(plans, st.sampled_from(["container", "task"]))
def test_round_trip_through_json(plan, item_key):
    doc = plan.to_dict(item_key)
    stored = json.loads(json.dumps(doc))
    back = PlacementPlan.from_dict(stored)
    assert back == plan
    assert back.to_dict(item_key) == doc


def test_keys_stored_beside_the_plan_are_ignored_when_named():
    plan = PlacementPlan(
        "rt-kube",
        [
            Decision("a", "n1", 2.0, (NodeVerdict("n1", scores={"b": 1.0}, total=2.0), NodeVerdict("n2", "Taints"))),
            Decision("b", None, None, (NodeVerdict("n1", "Fits", "full"),)),
        ],
        {"k": 3},
        {"elapsed_ms": 1.5},
    )
    stored = {**plan.to_dict(), "explain": ["..."]}
    assert PlacementPlan.from_dict(stored, ignore=("explain",)) == plan
    assert PlacementPlan.from_dict(stored).metrics == {"elapsed_ms": 1.5, "explain": ["..."]}
    assert plan.decision("b").pending and plan.decision("b").reasons() == {"n1": "full"}
    assert plan.decision("zzz") is None
    with pytest.raises(ValueError, match="decisions"):
        PlacementPlan.from_dict({"policy": "x"})
