"""ROS graphs and STL events from rosbag2 recordings (sqlite3 and MCAP) that the tests write with ``rosbags``."""

from __future__ import annotations

import pytest
from rosbags.typesys import Stores, get_typestore

from continuum.engine.containers.rosgraph import RosGraph, eq_3_12
from continuum.fleet.rosbag import BagError, events_from_bag, read_stats, rosgraph_from_bag

from .conftest import robot_topics, write_bag


def mean_size(topic: str) -> float:
    """What the recording holds per message of ``topic``: its CDR serialization, computed here independently."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    msgtype, _, count, make = robot_topics()[topic]
    return sum(len(store.serialize_cdr(make(store.types[msgtype], i), msgtype)) for i in range(count)) / count


def test_rates_and_sizes_per_topic(robot_bag):
    stats = read_stats(robot_bag)
    assert sorted(stats.topics) == ["/arrived", "/scan", "/speed"]
    assert stats.window_s == pytest.approx(1.0)
    assert {t: round(stats.rate_hz(t), 6) for t in stats.topics} == {"/scan": 10.0, "/speed": 20.0, "/arrived": 1.0}
    assert stats.topics["/scan"].messages == 11 and stats.topics["/speed"].messages == 21
    for topic in stats.topics:
        assert stats.topics[topic].mean_bytes == pytest.approx(mean_size(topic))


def test_rosgraph_with_named_nodes_gives_eq_3_12_bandwidth(robot_bag):
    doc = rosgraph_from_bag(
        robot_bag,
        name="run",
        publishers={"/scan": ["lidar"], "/speed": ["odom"]},
        subscribers={"/scan": ["planner", "mapper"], "/speed": ["planner"]},
    )
    graph = RosGraph.from_dict(doc)  # the server's own reader accepts it
    assert doc["format"] == "continuum.rosgraph/v1" and doc["meta"]["source"] == "rosbag2"
    assert set(graph.nodes) == {"lidar", "odom", "planner", "mapper", "arrived_pub"}
    assert doc["meta"]["unnamed_publishers"] == ["/arrived"]
    weights = graph.weights()
    scan = mean_size("/scan")
    # Eq. 3.12 for one shared topic: n_topics * m * M_size / T, with m / T the topic's rate
    assert weights[("lidar", "planner")] == pytest.approx(eq_3_12(1, 10.0, scan, 1.0), rel=1e-6)
    assert weights[("lidar", "mapper")] == pytest.approx(10.0 * scan, rel=1e-6)
    assert weights[("odom", "planner")] == pytest.approx(20.0 * mean_size("/speed"), rel=1e-6)
    assert ("arrived_pub", "planner") not in weights  # nobody subscribed to /arrived: no flow is invented


def test_rosgraph_only_selected_topics_and_placeholders(robot_bag):
    doc = rosgraph_from_bag(robot_bag, topics=["/speed"])
    assert [t["name"] for t in doc["topics"]] == ["/speed"]
    assert doc["topics"][0]["publishers"] == ["speed_pub"] and doc["topics"][0]["subscribers"] == []
    assert doc["topics"][0]["msg_type"] == "std_msgs/msg/Float64" and doc["topics"][0]["rate_hz"] == 20.0


def test_events_for_the_stl_monitors(robot_bag):
    events = list(events_from_bag(robot_bag))
    speed = [e for e in events if e[0] == "speed.data"]
    assert speed == [["speed.data", 0.5 * i, i * 50.0] for i in range(21)]
    arrived = [e for e in events if e[0] == "arrived.data"]
    assert arrived == [["arrived.data", False, 0.0], ["arrived.data", True, 1000.0]]
    assert not any(e[0].startswith("scan") for e in events)  # strings are not signals
    assert [e[2] for e in events] == sorted(e[2] for e in events)  # in recording order
    only = list(events_from_bag(robot_bag, topics=["/arrived"], signals=["arrived.data"]))
    assert [e[1] for e in only] == [False, True]


def test_nested_messages_flatten_to_dotted_signals(tmp_path):
    def odom(types, i):
        store = get_typestore(Stores.ROS2_HUMBLE).types
        vec = store["geometry_msgs/msg/Vector3"]
        return types(linear=vec(x=1.0 * i, y=0.0, z=0.0), angular=vec(x=0.0, y=0.0, z=0.25))

    bag = write_bag(tmp_path / "twist", "mcap", {"/robot1/cmd_vel": ("geometry_msgs/msg/Twist", 10.0, 3, odom)})
    events = list(events_from_bag(bag, signals=["robot1.cmd_vel.linear.x", "robot1.cmd_vel.angular.z"]))
    assert events == [
        ["robot1.cmd_vel.linear.x", 0.0, 0.0], ["robot1.cmd_vel.angular.z", 0.25, 0.0],
        ["robot1.cmd_vel.linear.x", 1.0, 100.0], ["robot1.cmd_vel.angular.z", 0.25, 100.0],
        ["robot1.cmd_vel.linear.x", 2.0, 200.0], ["robot1.cmd_vel.angular.z", 0.25, 200.0],
    ]  # fmt: skip


def test_bad_recordings_and_maps_are_refused(tmp_path, robot_bag):
    with pytest.raises(BagError, match="no such file"):
        read_stats(tmp_path / "missing")
    (tmp_path / "notabag").mkdir()
    (tmp_path / "notabag" / "metadata.yaml").write_text("rosbag2_bagfile_information: [\n")
    with pytest.raises(BagError, match=r"metadata\.yaml: not YAML"):
        read_stats(tmp_path / "notabag")
    with pytest.raises(BagError, match="'/cmd' is not in the recording"):
        rosgraph_from_bag(robot_bag, publishers={"/cmd": ["x"]})
    with pytest.raises(BagError, match="list of node names"):
        rosgraph_from_bag(robot_bag, publishers={"/scan": "lidar"})
    with pytest.raises(BagError, match="no topic '/odom'"):
        list(events_from_bag(robot_bag, topics=["/odom"]))
