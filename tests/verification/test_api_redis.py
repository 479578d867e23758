"""The event endpoint with a running monitor handler: events go to the handler's Redis stream, the handler
(a real process) evaluates them, and the handlers' sync brings its violations and verdicts back."""

import os
import subprocess
import sys
import time
import uuid

import pytest

from apps.verification.models import Handler, Monitor, MonitorVerdict, Violation
from continuum.verification_runtime.bus import Bus

from .test_runtime import REDIS_URL, ROOT, _redis_or_fail, _wait

pytestmark = [pytest.mark.services, pytest.mark.django_db]


@pytest.fixture
def network(settings, cluster):
    _redis_or_fail()
    settings.CONTINUUM_VERIFICATION_REDIS_URL = REDIS_URL
    settings.CONTINUUM_VERIFICATION_PREFIX = f"cvapi{uuid.uuid4().hex[:8]}"
    bus = Bus(REDIS_URL, prefix=f"{settings.CONTINUUM_VERIFICATION_PREFIX}:{cluster.pk}")
    procs = []

    def start(name, *extra):
        cmd = [
            sys.executable,
            "-m",
            "continuum.verification_runtime.handler",
            "--name",
            name,
            "--redis",
            REDIS_URL,
            "--prefix",
            bus.prefix,
            "--stats-period",
            "0.1",
            "--discovery",
            "0.2",
            "--free-cpu",
            "80",
            *extra,
        ]
        procs.append(subprocess.Popen(cmd, cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)}))
        _wait(lambda: name in bus.handlers(), what=f"handler {name} reporting")
        return procs[-1]

    yield bus, start
    for p in procs:
        if p.poll() is None:
            p.kill()
            p.wait(5)
    bus.clear()


def test_events_reach_a_running_handler_and_its_verdicts_come_back(api, cluster, network):
    bus, start = network
    r = api.post(
        "/api/v1/assertions/", {"name": "arrives", "text": "G(speed > 0 -> F[0,5000](arrived))"}, format="json"
    )
    node0 = cluster.nodes.get(name="node0")
    r = api.post(
        "/api/v1/monitors/",
        {"assertion": r.data["id"], "cluster": cluster.pk, "name": "m1", "node": node0.pk},
        format="json",
    )
    monitor = Monitor.objects.get(pk=r.data["id"])
    handler = start("node0")
    events = [
        ["speed", 3.0, 1000],
        ["arrived", False, 1000],
        ["arrived", True, 4000],
        ["speed", 0, 5000],
        ["arrived", False, 6000],
        ["speed", 5.0, 10000],
        ["speed", 0, 12000],
        ["speed", 0, 16000],
    ]
    r = api.post("/api/v1/events/", {"cluster": cluster.pk, "events": events}, format="json")
    assert r.status_code == 202 and r.data == {"routed": "redis", "events": 8, "handlers": ["node0"]}
    assert bus.monitors()["m1"]["assertion"] == "G(speed > 0 -> F[0,5000](arrived))"
    assert bus.allocation() == {"m1": "node0"}
    monitor.refresh_from_db()
    assert monitor.state is None  # not evaluated here
    bus.end_events()
    bus.send("node0", "SHUTDOWN")
    assert handler.wait(30) == 0
    r = api.post("/api/v1/handlers/sync/", {"cluster": cluster.pk}, format="json")
    assert r.status_code == 200 and r.data["summary"]["violations"] == 1 and r.data["summary"]["verdicts"] == 1
    v = Violation.objects.get(monitor=monitor)
    assert (v.instance_start_ms, v.time_ms, v.handler) == (10000.0, 16000.0, "node0")
    assert MonitorVerdict.objects.get(monitor=monitor).verdict == "fail"
    h = Handler.objects.get(node=node0)
    assert h.last_seen is not None and h.free_cpu == 80.0
    # a second sync stores nothing twice
    r = api.post("/api/v1/handlers/sync/", {"cluster": cluster.pk}, format="json")
    assert r.data["summary"]["violations"] == 0 and Violation.objects.count() == 1


def test_without_a_live_handler_events_are_evaluated_in_process(api, cluster, network):
    bus, _ = network
    bus.report("node0", {"wall": time.time() - 60, "free_cpu": 50})  # a handler that stopped a minute ago
    r = api.post("/api/v1/assertions/", {"name": "a", "text": "G(x > 1 -> F[0,10](y))"}, format="json")
    api.post("/api/v1/monitors/", {"assertion": r.data["id"], "cluster": cluster.pk, "name": "m"}, format="json")
    r = api.post(
        "/api/v1/events/", {"cluster": cluster.pk, "events": [["x", 2, 0], ["x", 0, 20], ["x", 0, 30]]}, format="json"
    )
    assert r.status_code == 200 and r.data["routed"] == "in-process" and len(r.data["violations"]) == 1
    assert bus.read_events("0-0") == []


def test_allocation_applied_to_running_handlers_migrates_without_losing_events(api, cluster, network):
    """The MILP (run through the API) moves a monitor off an overloaded handler while events flow; the
    handlers migrate it (Fig. 3.43) and its verdicts equal an unmigrated in-process evaluation."""
    from apps.verification.models import MigrationEvent
    from continuum.engine.verification.stl_monitor import Monitor as EngineMonitor

    bus, start = network
    text = "G(x >= 7 -> F[0,40](y >= 7))"
    r = api.post("/api/v1/assertions/", {"name": "response", "text": text}, format="json")
    node0 = cluster.nodes.get(name="node0")
    api.post(
        "/api/v1/monitors/",
        {"assertion": r.data["id"], "cluster": cluster.pk, "name": "m1", "node": node0.pk},
        format="json",
    )
    # node0: 80 % free, threshold 19 %: room for 1 % of monitors; the monitor costs 2 % -> it must leave
    h0 = start("node0", "--threshold", "19", "--monitor-cpu", "2")
    h1 = start("node1", "--monitor-cpu", "2")
    events = [("x" if i % 3 else "y", (i * 7) % 11, i * 5) for i in range(600)]
    first, second = events[:300], events[300:]
    assert api.post("/api/v1/events/", {"cluster": cluster.pk, "events": first}, format="json").status_code == 202
    _wait(lambda: "m1" in bus.handlers()["node0"].get("monitor_cpu", {}), what="m1 running on node0")
    api.post("/api/v1/handlers/sync/", {"cluster": cluster.pk}, format="json")
    r = api.post("/api/v1/allocations/", {"cluster": cluster.pk, "apply": True}, format="json")
    assert r.data["state"] == "succeeded", r.data
    move = MigrationEvent.objects.get(run_id=r.data["result"]["allocation_run"])
    assert (move.monitor_name, move.source, move.target) == ("m1", "node0", "node1")
    assert api.post("/api/v1/events/", {"cluster": cluster.pk, "events": second}, format="json").status_code == 202
    _wait(lambda: any(k == "migrated" for k, _ in bus.acks()), what="the migration")
    bus.end_events()
    for name in ("node0", "node1"):
        bus.send(name, "SHUTDOWN")
    assert h0.wait(30) == 0 and h1.wait(30) == 0
    api.post("/api/v1/handlers/sync/", {"cluster": cluster.pk}, format="json")
    reference = EngineMonitor(text)
    want = reference.feed(events) + reference.flush()
    got = Violation.objects.filter(monitor__name="m1").order_by("instance_start_ms")
    assert len(want) > 0
    assert [(v.instance_start_ms, v.time_ms) for v in got] == [(w.instance_start, w.time) for w in want]
    assert MonitorVerdict.objects.get(monitor__name="m1").handler == "node1"
    move.refresh_from_db()
    assert move.events_moved is not None  # the instants node0 handed over
    assert Monitor.objects.get(name="m1").node.name == "node1"
