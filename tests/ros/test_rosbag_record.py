"""Recordings made by Debian's ROS 1 (``rosbag record``, plain, bz2 and lz4 chunks) from real rospy nodes, read by
the fleet client with ``rosbags``: every topic, its publisher's node name, its rate and size, and its events."""

from __future__ import annotations

import subprocess

import pytest

from continuum.fleet.rosbag import describe_bag, events_from_bag, rosgraph_from_bag

pytestmark = pytest.mark.ros


@pytest.mark.parametrize("compression", [None, "--bz2", "--lz4"])
def test_rosbag_record_of_rospy_nodes(ros1, tmp_path, compression):
    ros1.node("lidar", publish=[{"topic": "/scan", "rate": 20, "bytes": 2000}])
    ros1.node("odom", publish=[{"topic": "/odom_text", "rate": 50, "bytes": 64},
                               {"topic": "/speed", "rate": 25, "type": "float64"}], subscribe=["/scan"])  # fmt: skip
    out = tmp_path / "run.bag"
    argv = ["rosbag", "record", "-O", str(out), "--duration=3", "/scan", "/odom_text", "/speed"]
    done = subprocess.run(argv + ([compression] if compression else []), env=ros1.env, capture_output=True,
                          text=True, timeout=120)  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]

    info = {t["name"]: t for t in describe_bag(out)["topics"]}
    assert set(info) == {"/scan", "/odom_text", "/speed"}
    assert info["/scan"]["msg_type"] == "std_msgs/msg/String" and info["/scan"]["decodable"]
    assert info["/scan"]["msg_bytes"] == 2000 and info["/odom_text"]["msg_bytes"] == 64  # ROS 1 serialized sizes
    # rosbag stamps messages as they arrive: the publishers' timers, within 10 %
    assert info["/scan"]["rate_hz"] == pytest.approx(20, rel=0.1)
    assert info["/odom_text"]["rate_hz"] == pytest.approx(50, rel=0.1)
    assert info["/scan"]["messages"] >= 30

    doc = rosgraph_from_bag(out)  # rosbag1 keeps each publisher's node name
    assert {t["name"]: t["publishers"] for t in doc["topics"]} == {
        "/scan": ["/lidar"], "/odom_text": ["/odom"], "/speed": ["/odom"]}  # fmt: skip
    assert doc["meta"]["source"] == "rosbag1"

    # std_msgs/String holds no numeric field; /speed's values are the publisher's sequence numbers: consecutive,
    # so nothing was lost between rospy, rosbag and the reader, and times grow
    events = list(events_from_bag(out))
    assert {e[0] for e in events} == {"speed.data"}
    values = [e[1] for e in events]
    assert values == [values[0] + i for i in range(len(values))] and len(values) >= 50
    assert [e[2] for e in events] == sorted(e[2] for e in events)
