"""STL monitors on a live ROS 1 topic: a rospy node publishes its sequence numbers on /speed at 100 Hz, the ROS 1
source (continuum/verification_runtime/ros1_source.py) streams them to two monitor handler processes, and the
monitors migrate between the handlers (Fig. 3.43) while the topic streams. Nothing is lost or doubled (the
sequence numbers in the trace are consecutive and the stream holds each once) and every verdict equals that
of ``stl_check`` on the recorded trace."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pytest
from django.core.management import call_command

from continuum.verification_runtime.bus import Bus

pytestmark = pytest.mark.ros

ROOT = Path(__file__).resolve().parents[2]
REDIS_URL = os.environ.get("CONTINUUM_TEST_REDIS_URL", "redis://127.0.0.1:6379/15")
MONITORS = {
    "bound": "G(speed.data < 250)",
    # the next message within 1-12 ms of each: at 100 Hz a late timer (a gap over 12 ms) is a violation, so the
    # verdicts follow the real timing of the publisher and the machine
    "gap": "G(speed.data >= 0 -> F[1,12](speed.data >= 0))",
}


def wait(predicate, timeout=120.0, what="condition"):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


@pytest.fixture
def bus():
    b = Bus(REDIS_URL, prefix=f"cvros:{uuid.uuid4().hex[:10]}")
    b.redis.ping()
    yield b
    b.clear()


def stl_check(trace: Path, assertion: str) -> dict:
    out = io.StringIO()
    call_command("stl_check", str(trace), "--assertion", assertion, "--json", stdout=out)
    return json.loads(out.getvalue())


@pytest.fixture(params=["processes", "netns"])
def handler_hosts(request):
    """How the two handlers run: as processes here, or each on a host of its own (a network namespace that
    reaches Redis through a relay at its gateway address)."""
    if request.param == "processes":
        yield {"edge": ([], REDIS_URL), "cloud": ([], REDIS_URL)}
        return
    from urllib.parse import urlsplit

    from .netns import Relay, hosts

    target = urlsplit(REDIS_URL)
    with hosts(2) as (edge, cloud):
        relays = [Relay((h.gateway, 0), (target.hostname or "127.0.0.1", target.port or 6379)) for h in (edge, cloud)]
        try:
            yield {name: (h.argv(), f"redis://{h.gateway}:{r.port}{target.path}")
                   for name, h, r in (("edge", edge, relays[0]), ("cloud", cloud, relays[1]))}  # fmt: skip
        finally:
            for r in relays:
                r.close()


def test_monitors_migrate_between_handlers_while_a_topic_streams_at_100_hz(ros1, bus, tmp_path, handler_hosts):
    ros1.node("odom", publish=[{"topic": "/speed", "rate": 100, "type": "float64"}])
    for name, text in MONITORS.items():
        bus.register_monitor(name, text)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    handlers = {
        h: subprocess.Popen([*wrap, sys.executable, "-m", "continuum.verification_runtime.handler", "--name", h,
                             "--redis", url, "--prefix", bus.prefix, "--stats-period", "0.1"], cwd=ROOT, env=env)
        for h, (wrap, url) in handler_hosts.items()
    }  # fmt: skip
    source = None
    try:
        wait(lambda: len(bus.handlers()) == 2, what="handlers reporting")
        bus.send("edge", "EXEC", monitors=sorted(MONITORS))
        wait(lambda: sum(1 for k, _ in bus.acks() if k == "exec") == 2, what="EXEC acknowledged")
        trace = tmp_path / "trace.csv"
        source = subprocess.Popen([sys.executable, "-m", "continuum.verification_runtime.ros1_source", "--ros1",
                                   ros1.uri, "--redis", REDIS_URL, "--prefix", bus.prefix, "--duration", "8",
                                   "--trace", str(trace), "--end"], cwd=ROOT, env=env, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True)  # fmt: skip
        # migrate while the topic streams: edge -> cloud, then back
        host = dict.fromkeys(MONITORS, "edge")
        for round_ in range(2):
            time.sleep(2.0)
            for name in MONITORS:
                to = "cloud" if host[name] == "edge" else "edge"
                bus.send(host[name], "MIGRATE", monitor=name, to=to)
                host[name] = to
            wait(lambda r=round_: sum(1 for k, _ in bus.acks() if k == "migrated") == 2 * (r + 1), what="migrated")
        _, err = source.communicate(timeout=120)
        assert source.returncode == 0, err
        for h in handlers:
            bus.send(h, "SHUTDOWN")
        for p in handlers.values():
            assert p.wait(120) == 0
    finally:
        for p in [*handlers.values(), *([source] if source else [])]:
            if p.poll() is None:
                p.kill()
                p.wait(10)

    # nothing lost or doubled between rospy, the source and the stream: consecutive sequence numbers, once each
    rows = trace.read_text().splitlines()[1:]
    values = [float(r.split(",")[1]) for r in rows]
    assert values == [values[0] + i for i in range(len(values))] and len(values) >= 500
    stream = [e for _, e in bus.read_events("0-0", count=100_000) if e is not None]
    assert [e[1] for e in stream] == values

    verdicts: dict[str, dict] = {n: {"violations": [], "final": None, "handlers": set()} for n in MONITORS}
    for entry in bus.verdicts():
        v = verdicts[entry["monitor"]]
        v["handlers"].add(entry["handler"])
        if entry["kind"] == "violation":
            v["violations"].append((entry["body"]["time"], entry["body"]["instance_start"]))
        else:
            v["final"] = entry["body"]
    for name, text in MONITORS.items():
        want = stl_check(trace, text)
        got = verdicts[name]
        assert got["violations"] == [(v["time"], v["instance_start"]) for v in want["violations"]], name
        assert got["final"]["verdict"] == want["verdict"], name
    assert verdicts["bound"]["violations"]  # the seq passed 250: violations, found by both handlers in turn
    print("\nlive monitors:", len(values), "messages,", {n: len(v["violations"]) for n, v in verdicts.items()},
          "violations; migrations:", sum(1 for k, _ in bus.acks() if k == "migrated"))  # fmt: skip
