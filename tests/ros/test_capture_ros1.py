"""``python -m continuum.fleet capture --ros1``: a real roscore and rospy nodes publishing at known rates and sizes;
the captured graph has every node, topic, publisher and subscriber, rates and sizes within 20 %, the nodes' CPU
and memory from /proc; uploaded and clustered through the API. Unreachable or bad masters: one line, exit 2."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from continuum.engine.containers.rosgraph import RosGraph

pytestmark = pytest.mark.ros

ROOT = Path(__file__).resolve().parents[2]

#: name -> (publications, subscriptions, extra); publications: (topic, rate Hz, bytes or "float64")
NODES = {
    "lidar": ([("/scan", 20, 4000)], [], {}),
    "odom": ([("/odom_text", 50, 120), ("/speed", 25, "float64")], ["/scan"], {}),
    "planner": ([("/cmd", 10, 300)], ["/scan", "/speed"], {"burn": 0.5}),
    "logger": ([], ["/cmd", "/odom_text"], {}),
    "beacon_a": ([("/beacon", 5, 64)], [], {}),
    "beacon_b": ([("/beacon", 20, 64)], ["/cmd"], {}),
}


def start_nodes(ros1) -> None:
    for name, (pubs, subs, extra) in NODES.items():
        publish = [{"topic": t, "rate": hz, **({"type": "float64"} if size == "float64" else {"bytes": size})}
                   for t, hz, size in pubs]  # fmt: skip
        ros1.node(name, publish=publish, subscribe=subs, **extra)


def expected_topics() -> dict[str, tuple[set, set]]:
    out: dict[str, tuple[set, set]] = {}
    for name, (pubs, subs, _) in NODES.items():
        for t, _, _ in pubs:
            out.setdefault(t, (set(), set()))[0].add(f"/{name}")
        for t in subs:
            out.setdefault(t, (set(), set()))[1].add(f"/{name}")
    return out


def capture(*args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "continuum.fleet", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=300, env={**os.environ, **(env or {})})  # fmt: skip


def test_capture_of_a_live_ros1_graph(ros1, tmp_path):
    start_nodes(ros1)
    out = tmp_path / "graph.json"
    done = capture("capture", "--ros1", ros1.uri, "--duration", "5", "--out", str(out))
    assert done.returncode == 0, done.stderr
    doc = json.loads(out.read_text())
    graph = RosGraph.from_dict(doc)  # the server's own reader accepts it

    rospy_nodes = {f"/{n}" for n in NODES}
    assert set(graph.nodes) == rospy_nodes | {"/rosout"}
    topics = {t["name"]: t for t in doc["topics"]}
    for name, (pubs, subs) in expected_topics().items():
        assert set(topics[name]["publishers"]) == pubs, name
        assert set(topics[name]["subscribers"]) == subs, name
    # every rospy node logs to /rosout, which rosout subscribes to and republishes on /rosout_agg
    assert set(topics["/rosout"]["publishers"]) == rospy_nodes and topics["/rosout"]["subscribers"] == ["/rosout"]
    assert set(topics) == set(expected_topics()) | {"/rosout", "/rosout_agg"}

    figures = {}
    for name, (pubs, _, _) in NODES.items():
        for t, hz, size in pubs:
            topic = topics[t]
            assert topic["measured"] is True, topic
            rate = topic.get("publisher_rates_hz", {}).get(f"/{name}", topic["rate_hz"])
            assert rate == pytest.approx(hz, rel=0.2), (t, name, rate)
            assert topic["msg_bytes"] == pytest.approx(8 if size == "float64" else size, rel=0.2), t
            figures[(t, name)] = (rate, hz, topic["msg_bytes"])
    # two publishers at 5 and 20 Hz: each has its own rate, and the topic's rate_hz is their mean
    assert set(topics["/beacon"]["publisher_rates_hz"]) == {"/beacon_a", "/beacon_b"}
    print("\ncapture accuracy:", {f"{t} <- {n}": f"{r:.2f}/{hz} Hz, {b} B" for (t, n), (r, hz, b) in figures.items()})

    nodes = {n["name"]: n for n in doc["nodes"]}
    for name in rospy_nodes:
        assert nodes[name]["measured"] is True and nodes[name]["memory_mib"] > 5, nodes[name]
    # the planner keeps a thread busy half of the time: it uses more CPU than the idle logger
    assert nodes["/planner"]["cpu"] > 0.1 and nodes["/planner"]["cpu"] > 2 * nodes["/logger"]["cpu"]
    assert doc["meta"]["source"] == "ros1 capture" and doc["meta"]["master"] == ros1.uri


def test_unmeasurable_topics_say_why(ros1, tmp_path):
    ros1.node("listener", subscribe=["/nobody_publishes"])
    done = capture("capture", "--ros1", ros1.uri, "--duration", "1", "--topic", "/nobody_publishes")
    assert done.returncode == 0, done.stderr
    (topic,) = json.loads(done.stdout)["topics"]
    assert topic["measured"] is False and topic["why_unmeasured"] == "no publisher"


@pytest.mark.parametrize(
    ("uri", "message"),
    [
        ("http://127.0.0.1:{closed}/", "getSystemState failed (Connection refused)"),
        ("ftp://127.0.0.1:11311/", "must look like http://HOST:PORT/"),
        ("http://127.0.0.1:99999/", "bad port"),
        ("http://127.0.0.1:{web}/", "getSystemState"),
    ],
)
def test_bad_or_unreachable_masters_are_one_line(tmp_path, uri, message):
    import http.server
    import socket
    import threading

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        closed = s.getsockname()[1]
    web = http.server.ThreadingHTTPServer(("127.0.0.1", 0), http.server.SimpleHTTPRequestHandler)  # not XML-RPC
    threading.Thread(target=web.serve_forever, daemon=True).start()
    try:
        done = capture("capture", "--ros1", uri.format(closed=closed, web=web.server_address[1]), "--duration", "1")
    finally:
        web.shutdown()
        web.server_close()
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and message in done.stderr, done.stderr


@pytest.mark.django_db(transaction=True)
def test_captured_graph_is_uploaded_and_clustered(ros1, live_server, fleet_token, api, member):
    from apps.containers.models import RosGraph as RosGraphRow

    start_nodes(ros1)
    done = capture("--server", live_server.url, "--token", fleet_token.plaintext, "--json", "capture", "--ros1",
                   ros1.uri, "--duration", "3", "--upload", "--name", "live robot")  # fmt: skip
    assert done.returncode == 0, done.stderr
    row = RosGraphRow.objects.get(pk=json.loads(done.stdout)["id"])
    stored = {t["name"]: t for t in row.document["topics"]}
    assert stored["/scan"]["measured"] is True and stored["/scan"]["msg_bytes"] == 4000  # the fields survive
    assert {n["name"] for n in row.document["nodes"] if n.get("measured")} >= {f"/{n}" for n in NODES}

    response = api.post(f"/api/v1/rosgraphs/{row.pk}/cluster/", {"containers": 3}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded", job
    graph = row.graph
    scan_bps = graph.topics["/scan"].rate("/lidar") * 4000
    assert scan_bps == pytest.approx(80_000, rel=0.2)  # Eq. 3.12 from the measured rate and size

    page = member.get(f"/ros/{row.pk}/")
    assert page.status_code == 200 and b"/scan" in page.content
    from apps.containers.forms import ClusterForm

    form = {k: f.initial for k, f in ClusterForm().fields.items() if f.initial not in (None, "")}
    clustered = member.post(f"/ros/{row.pk}/cluster/", {**form, "containers": 2, "mode": "per_topic"})
    assert clustered.status_code == 302, clustered.content[:500]


@pytest.mark.parametrize(
    ("state", "types", "message"),
    [
        ("garbage", [], "getSystemState answered no [publishers, subscribers, services]"),
        ([[["/a", [1]]], [], []], [], "bad publishers entry"),
        ([[], [], []], 7, "getTopicTypes answered no list"),
        ([[["/a", ["/n"]]], [], []], [], "lookupNode"),  # a node the master cannot look up: said, not measured
    ],
)
def test_a_hostile_master_is_one_line_or_said(state, types, message):
    """A master that answers the Master API with the wrong shapes (an XML-RPC server made here)."""
    import threading
    from xmlrpc.server import SimpleXMLRPCServer

    server = SimpleXMLRPCServer(("127.0.0.1", 0), logRequests=False, allow_none=True)
    server.register_function(lambda caller: [1, "", state], "getSystemState")
    server.register_function(lambda caller: [1, "", types], "getTopicTypes")
    server.register_function(lambda caller, node: [-1, f"unknown node {node}", ""], "lookupNode")
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        done = capture("capture", "--ros1", f"http://127.0.0.1:{server.server_address[1]}/", "--duration", "0.5")
    finally:
        server.shutdown()
        server.server_close()
    if done.returncode == 0:  # the graph is still written: the node and topic say why they were not measured
        doc = json.loads(done.stdout)
        assert message in doc["topics"][0]["why_unmeasured"] and message in doc["nodes"][0]["why_unmeasured"]
    else:
        assert done.returncode == 2 and done.stderr.count("\n") == 1 and message in done.stderr, done.stderr
