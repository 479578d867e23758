"""The node agent for real: SCHED_DEADLINE on this machine's kernel, SIGXCPU counted, reports through the live API.

Needs root (or CAP_SYS_NICE) and a kernel with SCHED_DEADLINE; where they are missing the tests fail and say so
(nothing is skipped). The machine is shared and busy: the assertions are about what cannot depend on load (a
CPU hog with a runtime shorter than its work overruns; a sleeper with a generous runtime does not; bandwidth
past the kernel's admission is refused). Nothing waits a fixed time for something to happen: the tests wait for
the condition itself, with timeouts far above what a loaded machine needs, and the agents get long flush and HTTP
timeouts (the live server shares the CPUs with everything else).
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import socket
import struct
import subprocess
import sys
import threading
import time
from datetime import datetime
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HOG = "import time\nt = time.monotonic()\nwhile time.monotonic() - t < {s}: pass\n"
#: For agents that report to the live server: it may answer slowly when the machine is loaded.
PATIENT = ("--flush-timeout", "120", "--http-timeout", "30", "--allow-http")
#: The commands run as nobody (the agent drops root): the test's interpreter may sit under /root, out of its reach.
PYTHON = "/usr/bin/python3"


def wait_until(condition, timeout: float = 120, what: str = "the condition") -> None:
    """Poll ``condition`` until true; fail after ``timeout`` seconds (a bound for a stuck test, not a speed)."""
    end = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > end:
            pytest.fail(f"{what} did not happen within {timeout} s")
        time.sleep(0.05)


def command_policy(agent_pid: int) -> int | None:
    """The scheduling policy of the agent's command (6: SCHED_DEADLINE), None while it has none."""
    try:
        child = int(Path(f"/proc/{agent_pid}/task/{agent_pid}/children").read_text().split()[0])
        return os.sched_getscheduler(child) & 0xFF
    except (OSError, IndexError, ValueError):
        return None


@pytest.fixture(autouse=True, scope="module")
def deadline_capable():
    """Fail (not skip) where the agent cannot work: the suite runs as root on a SCHED_DEADLINE kernel."""
    if os.geteuid() != 0:
        pytest.fail("the node agent's tests need root (or CAP_SYS_NICE) to set SCHED_DEADLINE")
    probe = subprocess.run(
        ["chrt", "-d", "--sched-runtime", "1000000", "--sched-deadline", "10000000", "--sched-period", "10000000",
         "0", "true"], capture_output=True, text=True,
    )  # fmt: skip
    if probe.returncode != 0:
        pytest.fail(f"SCHED_DEADLINE is not usable here: chrt -d says {probe.stderr.strip()!r}")


def agent(*args: str, timeout: float = 300, **popen) -> tuple[int, dict | None, str]:
    """Run ``python -m continuum.agent run ARGS`` to the end: (status, the JSON it printed last, stderr)."""
    proc = subprocess.run([sys.executable, "-m", "continuum.agent", "run", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=timeout, **popen)  # fmt: skip
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    return proc.returncode, json.loads(lines[-1]) if lines else None, proc.stderr


def reports(api, container):
    response = api.get(f"/api/v1/rt-reports/?container_name={container}&limit=1000&ordering=received_at")
    assert response.status_code == 200
    return response.data["results"]


def test_hog_overruns_are_counted_and_reported(server):
    server["realtime"]("hog", period=10, deadline=10, wcet=2)
    status, out, err = agent("--realtime", "hog", "--server", server["url"], "--token", server["token"], "--node",
                             "node0", *PATIENT, "--json", "--", PYTHON, "-c", HOG.format(s=1.5))  # fmt: skip
    assert status == 0, err
    assert out["exit_code"] == 0 and not out["kernel_rejected"]
    assert (out["runtime_ms"], out["deadline_ms"], out["period_ms"]) == (2.0, 10.0, 10.0)  # read from the RealTime
    assert out["overruns"] > 0, "a CPU hog with 2 ms of runtime per 10 ms raised no SIGXCPU"
    assert out["reported"] == out["overruns"] and out["pending"] == 0
    rows = reports(server["api"], "hog")
    assert {r["node"] for r in rows} == {"node0"}
    assert sum(r["missed_period"] for r in rows) == out["overruns"]
    assert max(r["missed_total"] for r in rows) == out["overruns"]
    counted = [r for r in rows if r["missed_period"]]
    assert counted and all(r["miss_at"] and r["sent_at"] for r in counted)
    assert all(datetime.fromisoformat(r["miss_at"].replace("Z", "+00:00"))
               <= datetime.fromisoformat(r["sent_at"].replace("Z", "+00:00")) for r in counted)  # fmt: skip
    latest = server["api"].get("/api/v1/rt-monitorings/?container_name=hog").data["results"]
    assert [m["missed_total"] for m in latest] == [out["overruns"]]


def test_hog_over_the_threshold_is_evicted_by_the_reconcile(server):
    """Real overruns, reported with the pod's name, go through the monitor's reconcile like any report: the
    cluster's default threshold (10 per report) is crossed, a lower-class stateless pod on the node is the victim,
    the node is tainted, and the event keeps the agent's Eq. 3.19 stamps (missAt <= sentAt <= received)."""
    from apps.realtime.models import RealTime
    from tests.realtime.conftest import make_pod

    cluster = server["cluster"]
    row = RealTime.objects.get(pk=server["realtime"]("slam", period=10, deadline=10, wcet=2)["id"])
    RealTime.objects.filter(pk=row.pk).update(criticality="B")
    make_pod(cluster, "slam-0", "node0", "B", True, cpu=0.2, realtime=row, utilization=0.2, container="slam")
    make_pod(cluster, "logger", "node0", "A", True, cpu=1.0, utilization=0.1)
    status, out, err = agent("--realtime", "slam", "--pod", "slam-0", "--server", server["url"], "--token",
                             server["token"], "--node", "node0", *PATIENT, "--json", "--", PYTHON, "-c",
                             HOG.format(s=1.5))  # fmt: skip
    assert status == 0, err
    assert out["overruns"] > 10 and out["reported"] == out["overruns"]
    assert out["server_violations"] >= 1
    events = server["api"].get(f"/api/v1/rt-events/?cluster={cluster.pk}&kind=eviction").data["results"]
    assert len(events) == 1, events
    event = events[0]
    assert event["container"].endswith("/slam-0") and event["victim"].endswith("/logger")
    stamps = [datetime.fromisoformat(event[k].replace("Z", "+00:00")) for k in ("miss_at", "sent_at", "received_at")]
    assert stamps == sorted(stamps)
    taints = server["api"].get(f"/api/v1/rt-taints/?cluster={cluster.pk}").data["results"]
    assert [(t["node"], t["key"]) for t in taints] == [("node0", "rt.monitoring/violation")]


def test_sleeper_reports_none(server):
    server["realtime"]("sleeper", period=50, deadline=50, wcet=10)
    status, out, err = agent("--realtime", "sleeper", "--server", server["url"], "--token", server["token"],
                             "--node", "node0", *PATIENT, "--json", "--", "sleep", "1")  # fmt: skip
    assert status == 0, err
    assert out["overruns"] == 0 and out["reported"] == 0 and not out["kernel_rejected"]
    rows = reports(server["api"], "sleeper")
    assert rows, "not even the start and final reports arrived"
    assert all(r["missed_total"] == 0 for r in rows)


def _admission_capacity() -> float:
    runtime = int(Path("/proc/sys/kernel/sched_rt_runtime_us").read_text())
    period = int(Path("/proc/sys/kernel/sched_rt_period_us").read_text())
    return len(os.sched_getaffinity(0)) * runtime / period


def test_over_admitted_set_is_refused_by_the_kernel_and_reported(server):
    # Three 70 % deadline tasks: 2.1 CPUs of bandwidth, past 2 x 0.95 (the kernel's admission on this machine).
    # The admitted ones sleep until every agent is settled (its command a deadline task, or refused and ended):
    # however slowly the agents start, the set is complete at once, never an admitted one gone before the last.
    n = int(_admission_capacity() / 0.7) + 1
    procs = []
    try:
        for i in range(n):
            cmd = [sys.executable, "-m", "continuum.agent", "run", "--runtime-ms", "7", "--deadline-ms", "10",
                   "--period-ms", "10", "--server", server["url"], "--token", server["token"], "--node", "node0",
                   "--container", f"heavy{i}", *PATIENT, "--json", "--", "sleep", "600"]  # fmt: skip
            procs.append(subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True))
        wait_until(lambda: all(p.poll() is not None or command_policy(p.pid) == 6 for p in procs), 240,
                   "every agent's command admitted as a deadline task or refused")  # fmt: skip
        for p in procs:
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)  # forwarded: the admitted sleep ends
        results = []
        for p in procs:
            stdout, stderr = p.communicate(timeout=300)
            lines = [ln for ln in stdout.splitlines() if ln.startswith("{")]
            assert lines, f"agent ended with {p.returncode} and no JSON: {stderr}"
            results.append((p.returncode, json.loads(lines[-1]), stderr))
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
                p.communicate()
    refused = [r for r in results if r[1]["kernel_rejected"]]
    admitted = [r for r in results if not r[1]["kernel_rejected"]]
    assert refused, f"{n} tasks of 70 % were all admitted: {[r[1] for r in results]}"
    assert len(admitted) * 0.7 <= _admission_capacity()
    for status, out, stderr in refused:
        assert status == 75 and out["exit_code"] is None and out["overruns"] == 0
        assert len(stderr.strip().splitlines()) == 1 and "EBUSY" in stderr and "admission" in stderr
        assert out["rejection_reported"]
        rows = reports(server["api"], out["container"])
        assert [(r["missed_period"], r["missed_total"]) for r in rows] == [(1, 1)]  # the job that could not run
    for status, out, stderr in admitted:
        assert status == 128 + signal.SIGTERM and out["signal"] == signal.SIGTERM, stderr
        assert out["exit_code"] is None and out["overruns"] == 0


class _Forwarder:
    """A TCP front for the live server, listening from the start on a port of its own. Until ``up`` is set the
    server is down: each request is read (to see what the agent was trying to deliver) and answered with a reset,
    the agent's attempt fails; then connections are forwarded to ``target``."""

    def __init__(self, target: tuple[str, int]):
        self.target = target
        self.up = threading.Event()
        self.dropped: list[dict] = []  # the bodies of the requests that failed
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(16)
        self.port = self.sock.getsockname()[1]
        threading.Thread(target=self._accept, daemon=True).start()

    def _accept(self) -> None:
        while True:
            try:
                client, _ = self.sock.accept()
            except OSError:
                return
            if not self.up.is_set():
                threading.Thread(target=self._drop, args=(client,), daemon=True).start()
                continue
            upstream = socket.create_connection(self.target)
            for a, b in ((client, upstream), (upstream, client)):
                threading.Thread(target=self._pump, args=(a, b), daemon=True).start()

    def _drop(self, client: socket.socket) -> None:
        data = b""
        with contextlib.suppress(OSError, ValueError):
            client.settimeout(60)
            while b"\r\n\r\n" not in data and (chunk := client.recv(65536)):
                data += chunk
            head, _, body = data.partition(b"\r\n\r\n")
            length = next(int(line.split(b":", 1)[1]) for line in head.split(b"\r\n")
                          if line.lower().startswith(b"content-length:"))  # fmt: skip
            while len(body) < length and (chunk := client.recv(65536)):
                body += chunk
            self.dropped.append(json.loads(body))
        client.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))  # close = reset
        client.close()

    def missed(self) -> int:
        """Overruns in the largest batch the agent failed to deliver (each attempt resends all that wait)."""
        return max((sum(r["missedDeadlinesPeriod"] for r in body["reports"]) for body in self.dropped), default=0)

    @staticmethod
    def _pump(a: socket.socket, b: socket.socket) -> None:
        try:
            while data := a.recv(65536):
                b.sendall(data)
        except OSError:
            pass
        finally:
            for s in (a, b):
                with contextlib.suppress(OSError):
                    s.shutdown(socket.SHUT_RDWR)

    def close(self) -> None:
        self.sock.close()


def test_server_unreachable_then_back_loses_no_count(server, live_server):
    host, live_port = live_server.url.split("//")[1].split(":")
    proxy = _Forwarder((host, int(live_port)))
    cmd = [sys.executable, "-m", "continuum.agent", "run", "--runtime-ms", "2", "--deadline-ms", "10", "--period-ms",
           "10", "--server", f"http://127.0.0.1:{proxy.port}", "--token", server["token"], "--node", "node0",
           "--container", "intermittent", "--interval", "0.2", "--max-backoff", "1", *PATIENT, "--json", "--",
           PYTHON, "-c", HOG.format(s=4)]  # fmt: skip
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        # The server comes back only once the agent failed to deliver counted overruns (not after a fixed time).
        wait_until(lambda: proxy.missed() > 0 or proc.poll() is not None, 240,
                   "a failed delivery of counted overruns")  # fmt: skip
        if proc.poll() is not None:
            pytest.fail(f"the agent ended before the server came back: {proc.returncode} {proc.communicate()}")
        proxy.up.set()
        stdout, stderr = proc.communicate(timeout=300)
    finally:
        proxy.close()
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    out = json.loads(stdout.splitlines()[-1])
    assert proc.returncode == 0, stderr
    assert out["report_failures"] >= len(proxy.dropped) > 0
    assert out["overruns"] >= proxy.missed() > 0
    assert out["reported"] == out["overruns"] and out["pending"] == 0
    rows = reports(server["api"], "intermittent")
    assert sum(r["missed_period"] for r in rows) == out["overruns"]
    assert max(r["missed_total"] for r in rows) == out["overruns"]


def test_signals_reach_the_command_and_its_status_is_the_agents():
    proc = subprocess.Popen([sys.executable, "-m", "continuum.agent", "run", "--runtime-ms", "5", "--deadline-ms",
                             "50", "--period-ms", "50", "--json", "--", "sleep", "600"], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        # The command becomes a deadline task (policy 6; the agent adds reset-on-fork) at its exec.
        wait_until(lambda: command_policy(proc.pid) == 6 or proc.poll() is not None, 240,
                   "the command running as a SCHED_DEADLINE task")  # fmt: skip
        assert proc.poll() is None, f"the agent ended early: {proc.returncode} {proc.communicate()}"
        proc.send_signal(signal.SIGTERM)
        stdout, _ = proc.communicate(timeout=300)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    out = json.loads(stdout.splitlines()[-1])
    assert proc.returncode == 128 + signal.SIGTERM
    assert out["signal"] == signal.SIGTERM and out["exit_code"] is None and not out["reporting"]


@pytest.mark.parametrize("key", ["-", "--", "-h"])
def test_a_token_that_starts_with_a_dash_is_the_tokens_value(server, fleet_token, key):
    """``secrets.token_urlsafe`` starts 1 key in 64 with '-': ``--token KEY`` takes it as the value, not as an
    option (argparse alone said "expected one argument", exit 2: the agent failed now and then at random)."""
    from apps.tenancy.models import FleetToken, new_token_key

    token = FleetToken(fleet=fleet_token.fleet, user=fleet_token.user, scope=FleetToken.Scope.ROBOT)
    token.set_key(key + new_token_key()[len(key) :])
    token.save()
    status, out, err = agent("--runtime-ms", "5", "--deadline-ms", "50", "--period-ms", "50", "--server",
                             server["url"], "--token", token.plaintext, "--node", "node0", "--container", "dashed",
                             *PATIENT, "--json", "--", "true")  # fmt: skip
    assert status == 0, err
    assert out["reports_acknowledged"] >= 1 and out["report_failures"] == 0, out  # the server took the key
    assert [r["missed_total"] for r in reports(server["api"], "dashed")] == [0]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--runtime-ms", "20", "--deadline-ms", "10", "--period-ms", "10", "--", "true"], "runtime <= deadline"),
        (["--runtime-ms", "2", "--deadline-ms", "10", "--period-ms", "10"], "no COMMAND"),
        (["--runtime-ms", "2", "--deadline-ms", "10", "--", "true"], "missing --period-ms"),
        (["--runtime-ms", "-2", "--deadline-ms", "10", "--period-ms", "10", "--", "true"], "positive"),
        (["--realtime", "x", "--", "true"], "--realtime needs --server"),
        (
            [
                "--server",
                "ftp://x",
                "--token",
                "t",
                "--runtime-ms",
                "1",
                "--deadline-ms",
                "2",
                "--period-ms",
                "2",
                "--",
                "true",
            ],
            "http(s) URL",
        ),
        (
            [
                "--server",
                "http://x",
                "--token",
                "--runtime-ms",
                "1",
                "--deadline-ms",
                "2",
                "--period-ms",
                "2",
                "--",
                "true",
            ],
            "argument --token: expected one argument",
        ),  # an option where the value should be: not taken
        (["--runtime-ms", "1", "--deadline-ms", "2", "--period-ms", "2", "--container"], "expected one argument"),
    ],
)
def test_bad_command_line_exits_2_with_one_line(args, message):
    status, out, err = agent(*args)
    assert status == 2 and out is None
    assert len(err.strip().splitlines()) == 1 and message in err


def test_realtime_without_a_wcet_for_this_node_is_refused(server):
    server["realtime"]("elsewhere", period=10, deadline=10, wcet=2, node="node1")
    status, _, err = agent("--realtime", "elsewhere", "--server", server["url"], "--token", server["token"],
                           "--node", "node0", "--allow-http", "--", "true")  # fmt: skip
    assert status == 2 and "no WCET for node 'node0'" in err and "node1" in err
    status, _, err = agent("--realtime", "nowhere", "--server", server["url"], "--token", server["token"],
                           "--node", "node0", "--allow-http", "--", "true")  # fmt: skip
    assert status == 2 and "no RealTime 'nowhere'" in err


def test_command_not_found_is_127():
    status, out, err = agent("--runtime-ms", "1", "--deadline-ms", "10", "--period-ms", "10", "--json", "--",
                             "/nonexistent/command")  # fmt: skip
    assert status == 127 and out["exit_code"] is None and "No such file" in err


def test_the_agent_needs_no_django():
    """It runs on a robot without the rest of Continuum: importing it loads no Django, DRF or Celery."""
    code = ("import sys, continuum.agent.cli\n"
            "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('django', 'rest_framework', 'celery'))\n"
            "print(bad)")  # fmt: skip
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
