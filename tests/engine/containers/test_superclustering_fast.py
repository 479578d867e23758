"""The fast super-clustering (shared index, arrays, explanations built on demand) against today's code kept in
``superclustering_reference``: the same decisions, verdicts, scores and metrics on random instances."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from continuum.engine.containers import superclustering as fast
from continuum.engine.core.cluster import Cluster, ClusterLink
from tests.engine.containers import superclustering_reference as ref


def same_plan(a, b):
    assert [d.item for d in a.decisions] == [d.item for d in b.decisions]
    assert a.placed() == b.placed()
    for x, y in zip(a.decisions, b.decisions, strict=True):
        assert (x.item, x.node, x.score) == (y.item, y.node, y.score)
        assert tuple(x.verdicts) == tuple(y.verdicts), x.item
    assert a.to_dict() == b.to_dict()
    assert a == b


@settings(max_examples=25, deadline=None)
@given(
    st.integers(1, 60),
    st.integers(1, 12),
    st.integers(0, 10**6),
    st.sampled_from([0.0, 39.0]),
    st.booleans(),
)
def test_superclustering_equals_the_reference(n, m, seed, overhead, noncanonical):
    wl, cl = ref.random_instance(n, m, seed, noncanonical=noncanonical)
    same_plan(fast.superclustering(wl, cl, overhead_mib=overhead), ref.superclustering(wl, cl, overhead_mib=overhead))


@settings(max_examples=15, deadline=None)
@given(st.integers(1, 50), st.integers(1, 10), st.integers(0, 10**6))
def test_default_kubernetes_equals_the_reference(n, m, seed):
    wl, cl = ref.random_instance(n, m, seed)
    same_plan(fast.default_kubernetes(wl, cl, seed=seed), ref.default_kubernetes(wl, cl, seed=seed))


@pytest.mark.parametrize(
    "weights",
    [{}, {"bandwidth": 2.0}, {"least_allocated": 1.0, "bandwidth": 0.5, "taint_toleration": 3.0},
     {"balanced_allocation": 1.0, "node_affinity": 0.0}],
)  # fmt: skip
def test_other_weights_equal_the_reference(weights):
    wl, cl = ref.random_instance(120, 15, 7)
    same_plan(fast.superclustering(wl, cl, weights=weights), ref.superclustering(wl, cl, weights=weights))


def test_a_larger_run_with_links_and_pending_containers():
    # 400 containers on 30 small nodes: many stay pending (every verdict a rejection); a ring of links with
    # equal latencies so the shortest-path choice between ties matters for the link loads.
    wl, cl = ref.random_instance(400, 30, 3, degree=6)
    names = list(cl.nodes)
    links = [ClusterLink(a, b, 100.0, 1.0) for a, b in zip(names, names[1:] + names[:1], strict=True)]
    cl = Cluster(cl.nodes, links)
    a, b = fast.superclustering(wl, cl), ref.superclustering(wl, cl)
    assert any(d.pending for d in a.decisions)
    same_plan(a, b)
    # Verdicts read out of order (later decisions first) are the same as in order.
    again = fast.superclustering(wl, cl)
    for d, e in zip(reversed(again.decisions), reversed(b.decisions), strict=True):
        assert tuple(d.verdicts) == tuple(e.verdicts)


@pytest.mark.parametrize("robot", [{}, {"drivers_on_robot": False}, {"robot_label": "zone=a"}])
def test_the_robot_board_filter_equals_the_reference(robot):
    wl, cl = ref.random_instance(150, 20, 11)
    a, b = fast.superclustering(wl, cl, **robot), ref.superclustering(wl, cl, **robot)
    if not robot:
        assert any(v.rejected_by == "RobotBoard" for d in a.decisions for v in d.verdicts)
    same_plan(a, b)
    same_plan(fast.default_kubernetes(wl, cl, seed=2, **robot), ref.default_kubernetes(wl, cl, seed=2, **robot))
