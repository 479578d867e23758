"""The default ROS clustering (Listing 3.20 then KL/FM refinement) against Listing 3.20 and Kernighan-Lin."""

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from continuum.engine import InputError
from continuum.engine.containers.cut_refinement import cut_weight, kl_partition, refine
from continuum.engine.containers.ros_clustering import cluster_ros
from continuum.engine.containers.rosgraph import RosGraph, load_rosgraph

DATA = Path(__file__).resolve().parents[2] / "data"
GRAPHS = ["autoware_reference_system.json", "autoware_reference_system.dot", "irobot_sierra_nevada.json"]


def path_graph() -> RosGraph:
    """Issue 27's minimal case: a-b at 1 B/s, b-c at 100 B/s."""
    return RosGraph.from_dict(
        {
            "nodes": [{"name": n} for n in "abc"],
            "topics": [
                {"name": "ab", "publishers": ["a"], "subscribers": ["b"], "rate_hz": 1, "msg_bytes": 1},
                {"name": "bc", "publishers": ["b"], "subscribers": ["c"], "rate_hz": 1, "msg_bytes": 100},
            ],
        }
    )


def groups(result):
    return [list(c.nodes) for c in result.containers]


def test_minimal_case_thesis_cuts_the_heavy_topic_default_does_not():
    thesis = cluster_ros(path_graph(), 2, method="thesis")
    assert groups(thesis) == [["a", "b"], ["c"]] and thesis.inter_container_bandwidth == 100
    default = cluster_ros(path_graph(), 2)
    assert groups(default) == [["a"], ["b", "c"]] and default.inter_container_bandwidth == 1
    assert default.params["method"] == "refined"


def test_unknown_method():
    with pytest.raises(InputError, match="unknown clustering method"):
        cluster_ros(path_graph(), 2, method="metis")


@pytest.mark.parametrize("name", GRAPHS)
@pytest.mark.parametrize("n", [2, 3, 4, 5, 6, 8, 12])
def test_default_cuts_at_most_kernighan_lin_and_listing_3_20_under_the_same_bound(name, n):
    graph = load_rosgraph((DATA / name).read_text())
    n = min(n, len(graph.nodes))
    weights = graph.weights()
    thesis = cluster_ros(graph, n, method="thesis")
    default = cluster_ros(graph, n)
    bound = max(len(g) for g in groups(thesis))
    kl = kl_partition(list(graph.nodes), weights, len(thesis.containers))
    assert max(len(g) for g in kl) <= bound  # KL is balanced, so it meets Listing 3.20's bound
    assert len(default.containers) == len(thesis.containers)
    assert max(len(g) for g in groups(default)) <= bound
    assert sorted(m for g in groups(default) for m in g) == sorted(graph.nodes)
    assert default.inter_container_bandwidth <= cut_weight(weights, kl) + 1e-6
    assert default.inter_container_bandwidth <= thesis.inter_container_bandwidth + 1e-6


@st.composite
def partitioned_graphs(draw):
    nodes = [f"v{i}" for i in range(draw(st.integers(2, 14)))]
    weights = {}
    for i, a in enumerate(nodes):
        for b in nodes[i + 1 :]:
            if draw(st.booleans()):
                weights[(a, b)] = draw(st.integers(1, 100))
    k = draw(st.integers(1, len(nodes)))
    labels = [i % k for i in range(len(nodes))]
    labels = draw(st.permutations(labels))
    start = [[v for v, lab in zip(nodes, labels, strict=True) if lab == i] for i in range(k)]
    bound = max(len(g) for g in start) + draw(st.integers(0, 3))
    return weights, start, bound


@settings(max_examples=120, deadline=None)
@given(partitioned_graphs())
def test_refine_keeps_count_and_bound_and_never_raises_the_cut(case):
    weights, start, bound = case
    out = refine(start, weights, bound)
    assert len(out) == len(start) and all(out)
    assert max(len(g) for g in out) <= bound
    assert sorted(v for g in out for v in g) == sorted(v for g in start for v in g)
    assert cut_weight(weights, out) <= cut_weight(weights, start) + 1e-9
