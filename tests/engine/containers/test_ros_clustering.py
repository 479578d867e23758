"""Listing 3.20 on the spec's reconstruction of Fig. 3.21, Eq. (3.13), and properties on random graphs."""

import random
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from continuum.engine import InputError
from continuum.engine.containers.ros_clustering import cluster_nodes, cluster_ros, max_containers, split_bandwidth
from continuum.engine.containers.rosgraph import RosGraph, load_rosgraph

DATA = Path(__file__).resolve().parents[2] / "data"
# Spec 02 section 2.8: consistent with every fact of Fig. 3.21 (v1-v3 = 5, v1-v4 = 4, v0 isolated). Not thesis data.
FIG_3_21 = {
    ("v1", "v3"): 5, ("v1", "v4"): 4, ("v2", "v4"): 3, ("v2", "v3"): 2, ("v3", "v5"): 2,
    ("v4", "v5"): 1, ("v6", "v7"): 3, ("v7", "v8"): 2, ("v8", "v9"): 4, ("v6", "v9"): 1,
}  # fmt: skip
V = [f"v{i}" for i in range(10)]


def clusters(result):
    return [list(c.nodes) for c in result.containers]


def test_fig_3_21_pass_by_pass():
    r = cluster_nodes(V, FIG_3_21, 2)
    assert r.culled == ["v0"]
    p1, p2, p3 = r.passes
    assert p1["clusters"] == [["v1", "v3"], ["v2", "v4"], ["v5"], ["v6", "v7"], ["v8", "v9"]]
    # Definition 3.2.1: sum linkage between the merged clusters.
    assert p1["edges"] == [["v1", "v2", 6.0], ["v1", "v5", 2.0], ["v2", "v5", 1.0], ["v6", "v8", 3.0]]
    # Pass 2 starts with {v5} (rank 1); {v2,v4} finds no free neighbour and is copied.
    assert p2["clusters"] == [["v1", "v3", "v5"], ["v2", "v4"], ["v6", "v7", "v8", "v9"]]
    assert p2["edges"] == [["v1", "v2", 7.0]]
    assert p3["clusters"] == [["v1", "v2", "v3", "v4", "v5"], ["v6", "v7", "v8", "v9"]]
    assert clusters(r) == p3["clusters"] and not r.guard_fired


def test_fig_3_21_three_containers_stops_after_pass_two():
    r = cluster_nodes(V, FIG_3_21, 3)
    assert len(r.passes) == 2
    assert clusters(r) == [["v1", "v3", "v5"], ["v2", "v4"], ["v6", "v7", "v8", "v9"]]


def test_fig_3_21_one_container_trips_the_guard():
    r = cluster_nodes(V, FIG_3_21, 1)
    assert r.guard_fired
    assert clusters(r) == [["v1", "v2", "v3", "v4", "v5"], ["v6", "v7", "v8", "v9"]]


def test_fig_3_21_variant_shows_the_greedy_cross_context_merge():
    r = cluster_nodes(V, {**FIG_3_21, ("v4", "v6"): 1}, 2)
    assert clusters(r) == [["v1", "v3", "v5"], ["v2", "v4", "v6", "v7", "v8", "v9"]]


def test_deterministic_whatever_the_input_order():
    base = clusters(cluster_nodes(V, FIG_3_21, 2))
    rng = random.Random(7)
    for _ in range(5):
        nodes = V[:]
        rng.shuffle(nodes)
        weights = {(b, a) if rng.random() < 0.5 else (a, b): w for (a, b), w in FIG_3_21.items()}
        assert clusters(cluster_nodes(nodes, weights, 2)) == base


def fig_graph(**node_attrs) -> RosGraph:
    """Fig. 3.21 as a ROS graph: one topic per edge, rate = weight, 1-byte messages."""
    topics = [
        {"name": f"/{a}_{b}", "publishers": [a], "subscribers": [b], "rate_hz": w, "msg_bytes": 1}
        for (a, b), w in FIG_3_21.items()
    ]
    nodes = [{"name": v, **node_attrs.get(v, {})} for v in V]
    return RosGraph.from_dict({"nodes": nodes, "topics": topics})


def test_cluster_ros_attaches_culled_nodes_and_accounts_bandwidth():
    r = cluster_ros(fig_graph(), 2, method="thesis")
    # v0 joins the lowest-demand cluster: equal (zero) demand, so the smaller one.
    assert clusters(r) == [["v0", "v6", "v7", "v8", "v9"], ["v1", "v2", "v3", "v4", "v5"]]
    assert r.inter_container_bandwidth == 0 and r.intra_container_bandwidth == sum(FIG_3_21.values())
    r3 = cluster_ros(fig_graph(), 3, method="thesis")
    # Left between {v1,v3,v5} and {v2,v4}: 6 + 1 (Definition 3.2.1).
    assert r3.inter_container_bandwidth == 7
    # The refinement (the default) finds a cut of 3 under the same bound (5 ROS nodes per container).
    refined = cluster_ros(fig_graph(), 3)
    assert refined.inter_container_bandwidth == 3 and len(refined.containers) == 3
    assert max(len(c.nodes) for c in refined.containers) <= 5


def test_culled_node_prefers_its_context():
    g = fig_graph(v0={"context": "vision"}, v2={"context": "vision"})
    assert clusters(cluster_ros(g, 2, method="thesis")) == [
        ["v0", "v1", "v2", "v3", "v4", "v5"],
        ["v6", "v7", "v8", "v9"],
    ]


def test_resource_tie_breaker_splits_the_heaviest_node():
    g = fig_graph(v3={"cpu": 2.0}, v4={"cpu": 1.0, "memory_mib": 500})
    r = cluster_ros(g, 2, max_cluster_share=0.4)
    # {v1..v5} holds 5 of 10 nodes > 40%: v3 (2 cores) leaves. {v0,v6..v9} holds 5 too and has no profile:
    # the node whose departure costs the least bandwidth leaves (v0, culled, 0).
    assert r.split_off == ["v3", "v0"]
    assert max(len(c.nodes) for c in r.containers) <= 4
    # Over a memory cap the memory-heaviest node leaves, whatever its CPU.
    r_mem = cluster_ros(g, 2, max_cluster_memory_mib=400)
    assert r_mem.split_off == ["v4"]
    with pytest.raises(InputError, match="share"):
        cluster_ros(g, 2, max_cluster_share=1.5)


def test_eq_3_13_bound():
    assert max_containers(320, 29) == 11
    assert max_containers(15827 - 250, 1.9) == 8198
    with pytest.raises(InputError, match="cannot hold one container"):
        max_containers(20, 29)
    with pytest.raises(InputError, match=r"exceed the Eq\. 3\.13 bound"):
        cluster_ros(fig_graph(), 3, available_mib=60, overhead_mib=29)
    assert cluster_ros(fig_graph(), 2, available_mib=60, overhead_mib=29).params["eq_3_13_bound"] == 2


@pytest.mark.parametrize("n", [0, -1, 2.5, True])
def test_bad_container_count(n):
    with pytest.raises(InputError, match="positive integer"):
        cluster_nodes(V, FIG_3_21, n)


def test_bad_weights():
    with pytest.raises(InputError, match="unknown ROS node 'x'"):
        cluster_nodes(V, {("v1", "x"): 1}, 2)
    with pytest.raises(InputError, match="invalid bandwidth"):
        cluster_nodes(V, {("v1", "v2"): -3}, 2)


def test_autoware_keeps_more_traffic_inside_than_one_node_per_container():
    g = load_rosgraph((DATA / "autoware_reference_system.json").read_text())
    total = sum(g.weights().values())
    previous = 0.0
    for n in (2, 4, 8, 12):
        r = cluster_ros(g, n)
        assert len(r.containers) == n
        assert sorted(m for c in r.containers for m in c.nodes) == sorted(g.nodes)
        assert r.inter_container_bandwidth + r.intra_container_bandwidth == pytest.approx(total)
        assert r.inter_container_bandwidth >= previous  # more containers, more traffic between them
        previous = r.inter_container_bandwidth
    assert previous < total  # one node per container would leave all of it


@st.composite
def weighted_graphs(draw):
    nodes = [f"v{i}" for i in range(draw(st.integers(1, 14)))]
    weights = {}
    for i, a in enumerate(nodes):
        for b in nodes[i + 1 :]:
            if draw(st.booleans()) and draw(st.booleans()):
                weights[(a, b)] = draw(st.integers(1, 9))
    return nodes, weights, draw(st.integers(1, 6))


@settings(max_examples=80, deadline=None)
@given(weighted_graphs())
def test_partition_and_count(case):
    nodes, weights, n = case
    r = cluster_nodes(nodes, weights, n)
    seen = [m for c in r.containers for m in c.nodes] + r.culled
    assert sorted(seen) == sorted(nodes)
    connected = len(nodes) - len(r.culled)
    if not r.guard_fired:
        assert len(r.containers) == min(n, connected)
    inter, intra = split_bandwidth(weights, r.assignment())
    assert inter + intra == sum(weights.values())
