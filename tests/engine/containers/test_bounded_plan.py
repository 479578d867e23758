"""A super-clustering plan's bounded explanations (issue 29): what the placement job stores instead of every
node's verdict. Checked against the full verdicts of the same run: the best candidates (the chosen node first)
with the same scores, the count of nodes each filter rejected, the first rejected nodes per filter as
examples; and every node's verdict again from the inputs alone."""

from collections import Counter

import pytest

from continuum.engine.containers.superclustering import (
    bounded_plan,
    decision_verdicts,
    default_kubernetes,
    superclustering,
)
from tests.engine.containers import superclustering_reference as ref


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("policy", ["superclustering", "default-kubernetes"])
def test_bounded_equals_the_full_verdicts_cut(seed, policy):
    workload, cluster = ref.random_instance(60, 25, seed=seed)
    run = superclustering if policy == "superclustering" else default_kubernetes
    bounded = bounded_plan(run(workload, cluster), top_k=3, examples=1)
    full = run(workload, cluster)
    assert [(d.item, d.node, d.score) for d in bounded.decisions] == [(d.item, d.node, d.score) for d in full.decisions]
    assert bounded.metrics == full.metrics
    for b, f in zip(bounded.decisions, full.decisions, strict=True):
        verdicts = list(f.verdicts)
        counts = Counter(v.rejected_by for v in verdicts if v.rejected_by)
        assert dict(b.rejections) == dict(counts)
        scored = [v for v in b.verdicts if not v.rejected_by]
        feasible = [v for v in verdicts if not v.rejected_by]
        assert len(scored) == min(3, len(feasible))
        assert all(v in verdicts for v in b.verdicts)  # same scores, totals and reasons
        if f.node is not None:
            assert scored[0].node == f.node
            rest = sorted((v.total for v in feasible if v.node != f.node), reverse=True)
            assert [v.total for v in scored[1:]] == rest[: len(scored) - 1]
        examples = [v for v in b.verdicts if v.rejected_by]
        first = {}
        for v in verdicts:
            if v.rejected_by:
                first.setdefault(v.rejected_by, v)
        assert len(examples) == len(first) and {v.rejected_by: v for v in examples} == first
    # bounding a plan read back (every verdict present) gives the same document
    again = bounded_plan(full)
    assert [d.to_dict()["rejections"] if d.rejections else {} for d in again.decisions] == [
        dict(Counter(v.rejected_by for v in f.verdicts if v.rejected_by)) for f in full.decisions
    ]


def test_every_verdict_of_one_decision_from_the_inputs():
    workload, cluster = ref.random_instance(40, 12, seed=5)
    full = superclustering(workload, cluster)
    item = full.decisions[17].item
    d = decision_verdicts("superclustering", workload, cluster, item)
    assert (d.node, d.score, tuple(d.verdicts)) == (full.decisions[17].node, full.decisions[17].score,
                                                    tuple(full.decisions[17].verdicts))  # fmt: skip
    with pytest.raises(KeyError):
        decision_verdicts("superclustering", workload, cluster, "no-such-container")
