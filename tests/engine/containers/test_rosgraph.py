"""ROS graph readers, Eq. (3.12) bandwidths and the Fig. 3.19 level proposal."""

import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from continuum.engine import InputError
from continuum.engine.containers.rosgraph import (
    RosGraph,
    eq_3_12,
    from_dot,
    irobot_msg_bytes,
    load_rosgraph,
    natural_key,
    pair,
    parse_dot,
    propose_levels,
)

DATA = Path(__file__).resolve().parents[2] / "data"
CONTRACT_EXAMPLE = {
    "format": "continuum.rosgraph/v1",
    "nodes": [{"name": "move_base", "level": "macro", "memory_mib": 120, "cpu": 0.4, "packages": ["nav2_core"]}],
    "topics": [
        {
            "name": "/scan",
            "publishers": ["laser_driver"],
            "subscribers": ["move_base", "amcl"],
            "rate_hz": 10,
            "msg_bytes": 8192,
        }
    ],
}


def autoware() -> RosGraph:
    return load_rosgraph((DATA / "autoware_reference_system.json").read_text())


# ---- Eq. 3.12 -------------------------------------------------------------------------------------
def test_eq_3_12_literal_acceptance_example():
    # Spec 02 acceptance 1: 2 topics, 100 messages, 1 kB average, T = 10 s -> 20 kB/s.
    assert eq_3_12(2, 100, 1000, 10) == 20_000
    with pytest.raises(InputError, match="window"):
        eq_3_12(1, 1, 1, 0)


def two_topic_graph() -> RosGraph:
    return RosGraph.from_dict(
        {
            "topics": [
                {"name": "/a", "publishers": ["p"], "subscribers": ["s"], "rate_hz": 10, "msg_bytes": 100},
                {"name": "/b", "publishers": ["s"], "subscribers": ["p"], "rate_hz": 5, "msg_bytes": 40},
            ]
        }
    )


def test_per_topic_sums_both_directions_and_literal_multiplies_by_topic_count():
    g = two_topic_graph()
    assert g.bandwidth("p", "s") == 10 * 100 + 5 * 40
    assert g.bandwidth("s", "p") == g.bandwidth("p", "s")
    # Literal Eq. 3.12: n_topics (2) * m/T (15 msg/s) * mean size (1200/15 B).
    assert g.bandwidth("p", "s", mode="literal") == pytest.approx(eq_3_12(2, 15, 1200 / 15, 1))
    assert g.shared_topics("p", "s") == ["/a", "/b"]
    with pytest.raises(InputError, match="unknown bandwidth mode"):
        g.weights("both")


def test_contract_example_creates_topic_only_nodes_and_subscribers_share_nothing():
    g = RosGraph.from_dict(CONTRACT_EXAMPLE)
    assert set(g.nodes) == {"move_base", "laser_driver", "amcl"}
    assert g.nodes["move_base"].packages == ("nav2_core",)
    assert g.bandwidth("laser_driver", "move_base") == 10 * 8192
    assert g.bandwidth("laser_driver", "amcl") == 10 * 8192
    # Two subscribers of /scan exchange no data: no edge between them.
    assert pair("amcl", "move_base") not in g.weights()


def test_measured_messages_over_window_and_period():
    g = RosGraph.from_dict(
        {
            "topics": [
                {"name": "/m", "publishers": ["a", "b"], "subscribers": ["c"], "messages": 600, "window_s": 60,
                 "msg_bytes": 10},
                {"name": "/p", "publishers": ["c"], "subscribers": ["a"], "period_ms": 50, "msg_bytes": 2},
            ]
        }
    )  # fmt: skip
    # 600 messages in 60 s shared by two publishers: 5 Hz each.
    assert g.bandwidth("a", "c") == pytest.approx(5 * 10 + 20 * 2)
    assert g.bandwidth("b", "c") == pytest.approx(5 * 10)


def test_round_trip_keeps_weights():
    g = RosGraph.from_dict(CONTRACT_EXAMPLE)
    again = RosGraph.from_dict(json.loads(json.dumps(g.to_dict())))
    assert again.weights() == g.weights()
    assert again.nodes["move_base"].level == "macro"


@pytest.mark.parametrize(
    ("doc", "message"),
    [
        ({"nodes": [{"name": "a", "level": "boss"}], "topics": []}, "ROS node 'a' has unknown level 'boss'"),
        ({"nodes": [{"name": "a"}, {"name": "a"}], "topics": []}, "duplicate ROS node name 'a'"),
        ({"nodes": [{"level": "driver"}], "topics": []}, r"nodes\[0\] has no string 'name'"),
        ({"topics": [{"name": "/t", "publishers": ["a"], "rate_hz": -1}]}, "topic '/t' has invalid rate_hz -1"),
        ({"topics": [{"name": "/t", "publishers": "a"}]}, "topic '/t': 'publishers' must be a list"),
        ({"topics": [{"name": "/t", "subscribers": [3]}]}, r"topic '/t': subscribers\[0\] must be a ROS node name"),
        ({"topics": [{"name": "/t"}, {"name": "/t"}]}, "duplicate topic '/t'"),
        ({"nodes": [{"name": "a", "cpu": "lots"}], "topics": []}, "ROS node 'a' has invalid cpu 'lots'"),
        ({"format": "continuum.dag/v1", "topics": []}, "unsupported format"),
        ({"topics": [{"name": "/t", "publishers": ["a"], "messages": 5}]}, "'window_s' a positive time"),
    ],
)
def test_bad_contract_input_names_the_element(doc, message):
    with pytest.raises(InputError, match=message):
        RosGraph.from_dict(doc)


def test_levels_given_win_and_aliases_are_accepted():
    g = RosGraph.from_dict(
        {
            "nodes": [{"name": "ctl", "level": "functionality_controller"}, {"name": "plan", "level": "Mission"}],
            "topics": [{"name": "/t", "publishers": ["plan"], "subscribers": ["ctl"], "rate_hz": 1}],
        }
    )
    assert g.levels() == {"ctl": "functionality", "plan": "mission"}
    # The proposal alone calls both boundary nodes drivers.
    assert propose_levels(g) == {"ctl": "driver", "plan": "driver"}


def test_natural_order():
    assert sorted(["v10", "v2", "v1", "V3"], key=natural_key) == ["v1", "v2", "V3", "v10"]
    assert pair("v10", "v9") == ("v9", "v10")


# ---- Autoware reference system --------------------------------------------------------------------
def test_autoware_rates_follow_node_semantics():
    g = autoware()
    assert (len(g.nodes), len(g.topics), len(g.weights())) == (24, 23, 29)
    rates = g.meta["topic_rates_hz"]
    assert rates["FrontLidarDriver"] == 10
    assert rates["EuclideanClusterSettings"] == 40  # 25 ms timer
    assert rates["EuclideanIntersection"] == 40  # intersection: each input drives its own output
    assert rates["EuclideanClusterDetector"] == 10
    assert rates["NDTLocalizer"] == pytest.approx(1000 / 120)  # fusion waits for its slowest input (120 ms)
    assert rates["BehaviorPlanner"] == 10  # timer; its subscriptions only cache
    assert g.bandwidth("EuclideanClusterSettings", "EuclideanClusterDetector") == 40 * 4096
    assert g.bandwidth("NDTLocalizer", "PointCloudMapLoader") == pytest.approx(4096 * 1000 / 120)
    # CPU demand = runtime x rate over callbacks: 0.22837 ms at 10 Hz and at 40 Hz.
    assert g.nodes["EuclideanClusterDetector"].cpu == pytest.approx(0.22837 * 50 / 1000)


def test_autoware_level_proposal():
    levels = autoware().levels()
    drivers = {n for n, lv in levels.items() if lv == "driver"}
    assert drivers == {
        "FrontLidarDriver", "RearLidarDriver", "PointCloudMap", "Visualizer", "Lanelet2Map",
        "EuclideanClusterSettings", "VehicleDBWSystem", "IntersectionOutput",
    }  # fmt: skip
    assert [n for n, lv in levels.items() if lv == "mission"] == ["BehaviorPlanner"]
    assert levels["PointCloudFusion"] == "macro" and levels["RayGroundFilter"] == "functionality"


def test_autoware_dot_matches_the_json_structure_and_skips_invisible_edges():
    dot = load_rosgraph((DATA / "autoware_reference_system.dot").read_text(), name="aw")
    js = autoware()
    assert len(dot.nodes) == len(js.nodes) == 24
    assert len(dot.weights()) == len(js.weights()) == 29

    def degrees(g):
        deg = dict.fromkeys(g.nodes, 0)
        for a, b in g.weights():
            deg[a] += 1
            deg[b] += 1
        return sorted(deg.values())

    assert degrees(dot) == degrees(js)
    # "Intersection Output" -> "Ray Ground Filter" exists only as an invisible layout edge.
    assert pair("Intersection Output", "Ray Ground Filter") not in dot.weights()
    # Unlabelled edges: the topic is named after the publisher, with unit rate and size by default.
    assert dot.bandwidth("Behavior Planner", "MPC Controller") == 1.0
    assert dot.topics["Behavior Planner"].subscribers == ("MPC Controller", "Vehicle Interface")


# ---- rqt_graph DOT --------------------------------------------------------------------------------
RQT_NODES_TOPICS = """digraph graphname {
  graph [bb="0,0,400,100", compound=True, rank=same, rankdir=LR, ranksep=0.2];
  node [label="\\N"];
  subgraph cluster___turtle1 {
    graph [label="/turtle1"];
    t___turtle1__cmd_vel [URL="topic:/turtle1/cmd_vel", label="/turtle1/cmd_vel", shape=box];
  }
  n___teleop [URL="/teleop", label="/teleop", shape=ellipse];
  n___sim [URL="/sim", label="/sim", shape=ellipse];
  n___teleop -> t___turtle1__cmd_vel [penwidth=1];
  t___turtle1__cmd_vel -> n___sim [penwidth=1];
}
"""

RQT_NODES_ONLY = """/* rqt_graph, Nodes only, with statistics */
digraph graphname {
  n___talker [label="/talker", shape=ellipse, URL="/talker"];
  n___listener [label="/listener", shape=ellipse, URL="/listener"];
  n___talker -> n___listener [label="/chatter\\n10.0 Hz // 1.5 ms", penwidth=1];
  n___listener -> n___talker [label="/ack", msg_bytes=64];
}
"""


def test_rqt_nodes_and_topics_mode():
    g = from_dot(RQT_NODES_TOPICS, default_rate_hz=2.0, default_msg_bytes=100)
    assert set(g.nodes) == {"/teleop", "/sim"}
    t = g.topics["/turtle1/cmd_vel"]
    assert (t.publishers, t.subscribers) == (("/teleop",), ("/sim",))
    assert g.bandwidth("/teleop", "/sim") == 200


def test_rqt_nodes_only_mode_reads_statistics_labels():
    g = from_dot(RQT_NODES_ONLY)
    assert set(g.topics) == {"/chatter", "/ack"}
    assert g.topics["/chatter"].rate("/talker") == 10.0
    assert g.bandwidth("/talker", "/listener") == 10.0 * 1 + 1.0 * 64


def test_dot_parser_handles_chains_subgraph_edges_ports_and_html():
    parsed = parse_dot("strict digraph { a:p1:n -> {b c} -> d; e [label=<<b>E</b>>];\n# cpp line\n}")
    pairs = {(e["src"], e["dst"]) for e in parsed["edges"]}
    assert pairs == {("a", "b"), ("a", "c"), ("b", "d"), ("c", "d")}
    assert parsed["nodes"]["e"]["label"] == "<b>E</b>"
    quoted = from_dot('digraph { "node" -> "edge" [label="/t"]; }')
    assert set(quoted.nodes) == {"node", "edge"} and quoted.topics["/t"].publishers == ("node",)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("digraph {\n a -> b;\n", "line 3: missing '}'"),
        ("digraph {\n a -> ;\n}", "line 2: expected a node id, got ';'"),
        ("graph {\n a -> b\n}", "line 2: edge operator '->' in a graph"),
        ("digraph {\n a @ b\n}", "line 2: unexpected character '@'"),
        ("digraph {\n a -> b [rate_hz=fast]\n}", "line 2: invalid rate_hz 'fast'"),
        ("tree { }", "line 1: expected 'graph' or 'digraph'"),
    ],
)
def test_dot_errors_name_the_line(text, message):
    with pytest.raises(InputError, match=message):
        from_dot(text)


# ---- iRobot ros2-performance ----------------------------------------------------------------------
def test_irobot_message_sizes():
    assert irobot_msg_bytes("stamped9_float32") == 20 + 9 * 4
    assert irobot_msg_bytes("stamped_int64") == 28
    assert irobot_msg_bytes("stamped1mb") == 20 + 1024 * 1024
    assert irobot_msg_bytes("stamped_vector", 10000) == 10020
    assert irobot_msg_bytes("my_custom_msg") is None


def test_irobot_sierra_nevada():
    g = load_rosgraph((DATA / "irobot_sierra_nevada.json").read_text(), name="sierra_nevada")
    assert g.meta["reader"] == "irobot" and len(g.nodes) == 10 and len(g.topics) == 13
    assert g.bandwidth("montreal", "lyon") == pytest.approx(100 * 56)  # amazon: 9 float32 at 10 ms
    assert g.bandwidth("mandalay", "ponce") == pytest.approx(10 * 10020)  # missouri: 10 kB vector at 100 ms
    # danube (28 B at 100 Hz) goes from montreal to hamburg, mandalay, ponce and geneva.
    assert g.bandwidth("montreal", "geneva") == pytest.approx(100 * 28)
    assert g.bandwidth("ponce", "georgetown") == pytest.approx(2 * 28)  # volga back, 500 ms


def test_irobot_errors():
    bad = {"nodes": [{"node_name": "n", "publishers": [{"topic_name": "t", "msg_type": "weird", "period_ms": 5}]}]}
    with pytest.raises(InputError, match="node 'n' publishers\\[0\\] \\(topic 't'\\): unknown msg_type 'weird'"):
        load_rosgraph(json.dumps(bad))
    bad = {"nodes": [{"node_name": "n", "publishers": [{"topic_name": "t", "msg_type": "stamped_int64"}]}]}
    with pytest.raises(InputError, match="needs 'period_ms' or 'freq_hz'"):
        load_rosgraph(json.dumps(bad))


def test_guessing_and_bad_json():
    with pytest.raises(InputError, match="malformed JSON at line 2 column"):
        load_rosgraph('{\n "topics": [,]}')
    with pytest.raises(InputError, match="cannot tell the ROS graph format"):
        load_rosgraph('{"stuff": 1}')
    with pytest.raises(InputError, match="unknown ROS graph format"):
        load_rosgraph("{}", "yaml")


# ---- properties -----------------------------------------------------------------------------------
@st.composite
def random_graphs(draw):
    names = [f"n{i}" for i in range(draw(st.integers(2, 8)))]
    topics = []
    for k in range(draw(st.integers(0, 10))):
        topics.append(
            {
                "name": f"/t{k}",
                "publishers": draw(st.lists(st.sampled_from(names), max_size=3, unique=True)),
                "subscribers": draw(st.lists(st.sampled_from(names), max_size=3, unique=True)),
                "rate_hz": draw(st.floats(0, 100)),
                "msg_bytes": draw(st.integers(0, 10_000)),
            }
        )
    return RosGraph.from_dict({"nodes": [{"name": n} for n in names], "topics": topics})


@settings(max_examples=60, deadline=None)
@given(random_graphs())
def test_weights_are_the_directed_flows_summed(g):
    flows = g.directed_traffic()
    assert sum(g.weights().values()) == pytest.approx(sum(sum(v.values()) for v in flows.values()))
    for (a, b), w in g.weights().items():
        assert natural_key(a) < natural_key(b)
        assert g.bandwidth(b, a) == w
        assert g.bandwidth(a, b, mode="literal") == pytest.approx(len(g.shared_topics(a, b)) * w)
    assert set(g.levels()) == set(g.nodes)
