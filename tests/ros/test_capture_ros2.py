"""``python -m continuum.fleet capture --ros2``: DDS participants (Cyclone DDS, made by the test in two processes)
that present themselves as ROS 2 nodes do, one announcing its nodes on ros_discovery_info (Foxy and later), one
naming its node in USER_DATA (Dashing/Eloquent). The capture finds every node, topic, publisher and subscriber,
measures the std_msgs topics within 20 % and says why the other type is not measured; an empty domain is one
line and exit 2."""

from __future__ import annotations

import json
import os
import random
import subprocess
import sys
from pathlib import Path

import pytest

from continuum.engine.containers.rosgraph import RosGraph

ROOT = Path(__file__).resolve().parents[2]
NODE = Path(__file__).with_name("dds_node.py")
#: Discovery on loopback only, unicast (no multicast on this machine's loopback): every participant of the test
#: finds the others through the peer list.
CYCLONE = (
    '<CycloneDDS><Domain Id="any"><General><Interfaces><NetworkInterface name="lo"/></Interfaces>'
    "<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>"
    '<MaxAutoParticipantIndex>40</MaxAutoParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers>'
    "</Discovery></Domain></CycloneDDS>"
)


@pytest.fixture
def dds(tmp_path):
    config = tmp_path / "cyclonedds.xml"
    config.write_text(CYCLONE)
    env = {**os.environ, "CYCLONEDDS_URI": config.as_uri()}
    domain = random.randrange(100, 230)  # other tests on this machine keep to their own domains
    procs: list[subprocess.Popen] = []

    def participant(spec: dict) -> None:
        proc = subprocess.Popen([sys.executable, str(NODE), json.dumps({"domain": domain, **spec})], env=env,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
        procs.append(proc)
        assert proc.stdout is not None and proc.stdout.readline().strip() == "ready", proc.stderr

    try:
        yield domain, env, participant
    finally:
        for proc in procs:
            proc.kill()
            proc.wait(timeout=30)


def capture(env: dict, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "continuum.fleet", "capture", *args], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300)  # fmt: skip


def test_capture_of_ros2_nodes_over_dds(dds, tmp_path):
    domain, env, participant = dds
    participant({"nodes": [
        {"name": "talker", "publish": [{"topic": "/chatter", "type": "String", "rate": 20, "bytes": 100}],
         "subscribe": [{"topic": "/cmd", "type": "Plan"}]},
        {"name": "odom", "namespace": "/robot", "publish": [{"topic": "/speed", "type": "Float64", "rate": 50}]},
    ]})  # fmt: skip
    participant({"style": "user_data", "nodes": [
        {"name": "planner", "publish": [{"topic": "/cmd", "type": "Plan", "rate": 10}],
         "subscribe": [{"topic": "/chatter", "type": "String"}, {"topic": "/speed", "type": "Float64"}]},
    ]})  # fmt: skip
    out = tmp_path / "graph.json"
    done = capture(env, "--ros2", "--domain", str(domain), "--duration", "4", "--out", str(out))
    assert done.returncode == 0, done.stderr
    doc = json.loads(out.read_text())
    RosGraph.from_dict(doc)

    assert {n["name"] for n in doc["nodes"]} == {"/talker", "/robot/odom", "/planner"}
    topics = {t["name"]: t for t in doc["topics"]}
    assert {t: (x["publishers"], sorted(x["subscribers"])) for t, x in topics.items()} == {
        "/chatter": (["/talker"], ["/planner"]),
        "/speed": (["/robot/odom"], ["/planner"]),
        "/cmd": (["/planner"], ["/talker"]),
    }
    assert topics["/chatter"]["msg_type"] == "std_msgs/msg/String" and topics["/chatter"]["measured"] is True
    assert topics["/chatter"]["rate_hz"] == pytest.approx(20, rel=0.2)
    assert topics["/chatter"]["msg_bytes"] == pytest.approx(100, rel=0.2)
    assert topics["/speed"]["rate_hz"] == pytest.approx(50, rel=0.2)
    assert topics["/speed"]["msg_bytes"] == 12  # CDR: 4 bytes of header + a float64
    assert topics["/cmd"]["measured"] is False and "my_msgs/msg/Plan cannot be read" in topics["/cmd"]["why_unmeasured"]
    print("\nros2 capture:", {t: (x["rate_hz"], x["msg_bytes"]) for t, x in topics.items()})
    nodes = {n["name"]: n for n in doc["nodes"]}
    assert all(n["measured"] and n["memory_mib"] > 5 for n in nodes.values()), nodes
    # the talker and odom nodes share one participant, hence one process
    assert doc["meta"]["pids"]["/talker"] == doc["meta"]["pids"]["/robot/odom"] != doc["meta"]["pids"]["/planner"]


def test_an_empty_domain_is_one_line(dds):
    domain, env, _ = dds
    done = capture(env, "--ros2", "--domain", str(domain), "--duration", "1")
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert f"no DDS participant answered in domain {domain}" in done.stderr
