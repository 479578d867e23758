"""Start-up is not a deadline miss (issue 32): overruns before the command is ready are counted apart
(``startup_overruns``, ``startupOverruns`` in reports), stored apart by the server and never evict.

Real processes under SCHED_DEADLINE; the reports go through the live API and its reconcile.
"""

from __future__ import annotations

import pytest

from tests.agent.test_agent import PATIENT, PYTHON, agent, reports

#: Sleeps 50 ms at a time for 2 s: after its start it uses far less than 5 ms per 50 ms period. It ends with
#: ``os._exit``: the interpreter's finalisation is work too (1 run in 8 here overran once at exit).
SLEEPER = "import os, time\nfor _ in range(40):\n    time.sleep(0.05)\nos._exit(0)\n"
#: Burns CPU for {hog} s from its first instruction (a long start-up), then sleeps {rest} s.
SLOW_START = "import time\nt = time.monotonic()\nwhile time.monotonic() - t < {hog}: pass\ntime.sleep({rest})\n"
#: Says it is ready at once, then burns CPU for 0.5 s: every overrun after the signal is a miss.
READY_THEN_HOG = (
    "import os, time\nos.write(int(os.environ['CONTINUUM_READY_FD']), b'1')\n"
    "t = time.monotonic()\nwhile time.monotonic() - t < 0.5: pass\n"
)


def test_a_python_start_up_is_not_counted_as_misses():
    """The issue's case: a Python command that sleeps 50 ms at a time under a 5 ms / 50 ms reservation. Without a
    warm-up its interpreter's start-up overruns; with the default one (20 periods) none of it is a miss."""
    timing = ("--runtime-ms", "5", "--deadline-ms", "50", "--period-ms", "50", "--json")
    status, bare, err = agent(*timing, "--warmup-periods", "0", "--", PYTHON, "-c", SLEEPER)
    assert status == 0, err
    assert bare["overruns"] >= 1 and bare["startup_overruns"] == 0 and bare["warmup_ms"] == 0
    status, out, err = agent(*timing, "--", PYTHON, "-c", SLEEPER)
    assert status == 0, err
    assert out["warmup_ms"] == 1000.0  # 20 periods of 50 ms
    assert out["overruns"] == 0, out


def test_readiness_ends_the_warm_up():
    status, out, err = agent("--runtime-ms", "2", "--deadline-ms", "10", "--period-ms", "10", "--warmup-ms",
                             "600000", "--json", "--", PYTHON, "-c", READY_THEN_HOG)  # fmt: skip
    assert status == 0, err
    assert out["ready_signalled"] and out["overruns"] > 0, out


@pytest.mark.parametrize(("warmup", "words"), [("-1", ">= 0"), ("nan", ">= 0"), ("x", "not a number")])
def test_bad_warmup_exits_2(warmup, words):
    status, out, err = agent("--runtime-ms", "1", "--deadline-ms", "10", "--period-ms", "10", "--warmup-ms",
                             warmup, "--", "true")  # fmt: skip
    assert status == 2 and out is None and words in err and len(err.strip().splitlines()) == 1
    status, _, err = agent("--runtime-ms", "1", "--deadline-ms", "10", "--period-ms", "10", "--warmup-ms", "1",
                           "--warmup-periods", "2", "--", "true")  # fmt: skip
    assert status == 2 and "not allowed with" in err


def test_start_up_overruns_reach_the_server_apart_and_never_evict(server):
    """A slow start (0.6 s of CPU at 2 ms per 10 ms: about 60 overruns, six times the eviction threshold) inside the
    RealTime's declared warm-up: reported as startupOverruns, stored apart, no violation, no eviction, no taint."""
    from apps.realtime.models import RealTime
    from tests.realtime.conftest import make_pod

    cluster = server["cluster"]
    row = server["realtime"]("slowstart", period=10, deadline=10, wcet=2)
    response = server["api"].patch(f"/api/v1/realtimes/{row['id']}/", {"warmup_ms": 5000}, format="json")
    assert response.status_code == 200 and response.data["warmup_ms"] == 5000
    RealTime.objects.filter(pk=row["id"]).update(criticality="B")
    make_pod(cluster, "slowstart-0", "node0", "B", True, cpu=0.2, realtime=RealTime.objects.get(pk=row["id"]),
             utilization=0.2, container="slowstart")  # fmt: skip
    make_pod(cluster, "logger", "node0", "A", True, cpu=1.0, utilization=0.1)
    status, out, err = agent("--realtime", "slowstart", "--pod", "slowstart-0", "--server", server["url"],
                             "--token", server["token"], "--node", "node0", *PATIENT, "--json", "--", PYTHON, "-c",
                             SLOW_START.format(hog=0.6, rest=0.2))  # fmt: skip
    assert status == 0, err
    assert out["warmup_ms"] == 5000  # read from the RealTime
    assert out["startup_overruns"] > 10 and out["overruns"] == 0, out
    assert out["startup_reported"] == out["startup_overruns"] and out["server_violations"] == 0
    rows = reports(server["api"], "slowstart")
    assert sum(r["startup_overruns"] for r in rows) == out["startup_overruns"]
    assert all(r["missed_period"] == 0 and r["missed_total"] == 0 and not r["violation"] for r in rows)
    assert server["api"].get(f"/api/v1/rt-events/?cluster={cluster.pk}").data["results"] == []
    assert server["api"].get(f"/api/v1/rt-taints/?cluster={cluster.pk}").data["results"] == []


@pytest.mark.parametrize("value", [-1, 1.5, "3", True, 2**31])
def test_a_bad_startup_count_is_a_400(server, value):
    body = {"cluster": server["cluster"].pk, "reports": [{"node": "node0", "containerName": "c",
            "missedDeadlinesPeriod": 0, "missedDeadlinesTotal": 0, "startupOverruns": value}]}  # fmt: skip
    response = server["api"].post("/api/v1/rt-reports/", body, format="json")
    assert response.status_code == 400 and "startupOverruns" in str(response.data)


@pytest.mark.parametrize("value", [-1, 3_600_001, "nan"])
def test_a_bad_warmup_on_the_realtime_is_a_400(server, value):
    row = server["realtime"]("warm", period=10, deadline=10, wcet=2)
    response = server["api"].patch(f"/api/v1/realtimes/{row['id']}/", {"warmup_ms": value}, format="json")
    assert response.status_code == 400 and "warmup_ms" in response.data
