"""The node agent's trust boundary (issue 25): the command cannot leave its reservation, the token goes nowhere
but ``--server``, over https unless told otherwise, and a redirected report is not delivered.

Real processes: the agent runs as root (as in CI), the command's own view of itself is measured from inside it.
"""

from __future__ import annotations

import http.server
import json
import os
import subprocess
import sys
import threading

import pytest

from tests.agent.test_agent import HOG, PYTHON, ROOT, agent

#: Run inside the command: who it is, what it may do to its own scheduling, what a child of it gets.
PROBE = r"""
import json, os
status = {l.split(":")[0]: int(l.split(":")[1], 16) for l in open("/proc/self/status") if l.startswith("Cap")}
nnp = [l.split()[1] for l in open("/proc/self/status") if l.startswith("NoNewPrivs")][0]
out = {"uid": os.getuid(), "euid": os.geteuid(), "gid": os.getgid(), "groups": os.getgroups(), "caps": status,
       "no_new_privs": nnp, "policy": os.sched_getscheduler(0), "token": os.environ.get("CONTINUUM_TOKEN")}
for name, policy, prio in (("fifo99", os.SCHED_FIFO, 99), ("rr1", os.SCHED_RR, 1), ("other", os.SCHED_OTHER, 0)):
    try:
        os.sched_setscheduler(0, policy, os.sched_param(prio))
        out[name] = "allowed"
    except OSError as exc:
        out[name] = exc.errno
pid = os.fork()
if pid == 0:
    os._exit(os.sched_getscheduler(0))
out["child_policy"] = os.WEXITSTATUS(os.waitpid(pid, 0)[1])
print("PROBE " + json.dumps(out), flush=True)
"""
SCHED_DEADLINE, SCHED_RESET_ON_FORK = 6, 0x40000000


def probe(*extra: str, env: dict[str, str] | None = None) -> tuple[dict, dict]:
    proc = subprocess.run([sys.executable, "-m", "continuum.agent", "run", "--runtime-ms", "20", "--deadline-ms",
                           "50", "--period-ms", "50", *extra, "--json", "--", PYTHON, "-c", PROBE], cwd=ROOT,
                          capture_output=True, text=True, timeout=300, env=env)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    inside = json.loads(next(ln for ln in lines if ln.startswith("PROBE "))[6:])
    return inside, json.loads(lines[-1])


def test_the_command_cannot_leave_its_reservation():
    env = dict(os.environ, CONTINUUM_TOKEN="the-fleet-token")
    inside, out = probe(env=env)
    assert os.geteuid() == 0  # the agent runs as root, as on a node
    assert (inside["uid"], inside["euid"], inside["gid"], inside["groups"]) == (65534, 65534, 65534, [])
    assert (out["command_uid"], out["command_gid"]) == (65534, 65534)
    assert inside["caps"] == {"CapInh": 0, "CapPrm": 0, "CapEff": 0, "CapBnd": 0, "CapAmb": 0}
    assert inside["no_new_privs"] == "1"
    # It is the deadline task, with reset-on-fork that it cannot clear...
    assert inside["policy"] == SCHED_DEADLINE | SCHED_RESET_ON_FORK
    # ...and every way out is refused by the kernel (EPERM), measured from inside: SCHED_FIFO 99 succeeded before.
    assert (inside["fifo99"], inside["rr1"], inside["other"]) == (1, 1, 1)
    assert inside["child_policy"] == 0  # a child it forks is SCHED_OTHER
    assert inside["token"] is None  # the fleet token is the agent's, not the command's
    assert out["agent_capabilities"] == ["CAP_KILL", "CAP_SYS_NICE"]


def test_user_option_and_root_refused():
    inside, out = probe("--user", "65534:65533")
    assert (inside["uid"], inside["gid"]) == (65534, 65533) and inside["caps"]["CapEff"] == 0
    for bad, words in (("0", "may not run as root"), ("root", "may not run as root"), ("65534:0", "root"),
                       ("no-such-user-x", "no user")):  # fmt: skip
        status, out, err = agent("--user", bad, "--runtime-ms", "1", "--deadline-ms", "10", "--period-ms", "10", "--",
                                 "true")  # fmt: skip
        assert status == 2 and out is None and words in err and len(err.strip().splitlines()) == 1, (bad, err)


def test_plain_http_needs_the_flag():
    status, out, err = agent("--server", "http://127.0.0.1:9", "--token", "t", "--runtime-ms", "1", "--deadline-ms",
                             "10", "--period-ms", "10", "--", "true")  # fmt: skip
    assert status == 2 and out is None and "plain http" in err and "--allow-http" in err
    assert len(err.strip().splitlines()) == 1


class _Recorder(http.server.ThreadingHTTPServer):
    """An HTTP server on a port of its own: ``redirect`` set, it answers every request with that redirect; else
    it answers 200 ``{}``. It records each request's method, path and Authorization header."""

    def __init__(self, redirect: str | None = None, code: int = 307):
        self.seen: list[tuple[str, str, str | None]] = []
        self.redirect, self.code = redirect, code
        recorder = self

        class Handler(http.server.BaseHTTPRequestHandler):
            def _answer(self) -> None:
                length = int(self.headers.get("Content-Length") or 0)
                self.rfile.read(length)
                recorder.seen.append((self.command, self.path, self.headers.get("Authorization")))
                if recorder.redirect:
                    self.send_response(recorder.code)
                    self.send_header("Location", recorder.redirect + self.path)
                    self.send_header("Content-Length", "0")
                    self.end_headers()
                    return
                body = b'{"results": []}'
                self.send_response(200)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)

            do_GET = do_POST = _answer

            def log_message(self, *args: object) -> None:
                pass

        super().__init__(("127.0.0.1", 0), Handler)
        threading.Thread(target=self.serve_forever, daemon=True).start()

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.server_address[1]}"


@pytest.mark.parametrize("code", [301, 302, 307, 308])
def test_a_redirect_is_refused_the_token_stays_and_nothing_counts_as_delivered(code):
    thief = _Recorder()
    front = _Recorder(redirect=thief.url, code=code)
    try:
        status, out, err = agent("--server", front.url, "--allow-http", "--token", "the-fleet-token", "--node", "n0",
                                 "--container", "redirected", "--runtime-ms", "2", "--deadline-ms", "10",
                                 "--period-ms", "10", "--flush-timeout", "5", "--json", "--", PYTHON, "-c",
                                 HOG.format(s=0.5))  # fmt: skip
        assert status == 0, err
        assert front.seen and all(s[2] == "Token the-fleet-token" for s in front.seen)
        assert thief.seen == []  # the token never reached the host the redirect named
        assert out["reported"] == 0 and out["reports_acknowledged"] == 0
        assert out["pending"] == out["overruns"] > 0
        assert "redirect" in out["report_error"] and thief.url in out["report_error"]
        assert len(front.seen) == 1  # a redirect is not retried (as a 4xx)
        # The RealTime lookup refuses it too: exit 2, one line, nothing sent to the thief.
        status, out, err = agent("--server", front.url, "--allow-http", "--token", "the-fleet-token", "--realtime",
                                 "x", "--node", "n0", "--", "true")  # fmt: skip
        assert status == 2 and "redirect" in err and len(err.strip().splitlines()) == 1
        assert thief.seen == []
    finally:
        for server in (front, thief):
            server.shutdown()
            server.server_close()
