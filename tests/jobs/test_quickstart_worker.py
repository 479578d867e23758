"""`scripts/start` runs jobs in a worker process of its own: a request that starts a job returns at once."""

import os
import signal
import time
from datetime import datetime
from pathlib import Path

import pytest

from benchmarks.quickstart_load import ROOT, QuickStart, free_port, request

pytestmark = pytest.mark.services


@pytest.fixture(scope="module")
def quickstart(tmp_path_factory):
    var = tmp_path_factory.mktemp("quickstart-jobs") / "var"
    server = QuickStart(ROOT, var, free_port())
    yield server, var
    server.stop()


def follow(server, job_id: str, timeout: float = 180) -> list[dict]:
    """The job as read every 50 ms until it ends."""
    seen, deadline = [], time.monotonic() + timeout
    while time.monotonic() < deadline:
        status, job = request(server.port, "GET", f"/api/v1/jobs/{job_id}/", token=server.token)
        assert status == 200, job
        seen.append(job)
        if job["state"] in ("succeeded", "failed", "cancelled"):
            return seen
        time.sleep(0.05)
    raise AssertionError(f"job {job_id} still {seen[-1]['state']} after {timeout} s")


def command_line(pid: int) -> str:
    return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()


def test_a_job_runs_in_the_worker_process_not_in_the_request(quickstart):
    server, var = quickstart
    # The demo's own first schedule was queued by load_demo before the worker started: the worker ran it.
    deadline = time.monotonic() + 180
    while True:
        status, schedules = request(server.port, "GET", "/api/v1/schedules/?limit=1", token=server.token)
        assert status == 200, schedules
        if schedules["results"] or time.monotonic() > deadline:
            break
        time.sleep(0.5)
    assert schedules["results"], "the demo's schedule job did not run"
    demo = schedules["results"][0]
    body = {"algorithm": "heft", "cluster": demo["cluster"], "frames": 40}
    status, job = request(
        server.port, "POST", f"/api/v1/applications/{demo['application']}/schedule/", body, token=server.token
    )
    assert status == 202, job
    # The answer came before the job ran: it was queued (in-process runs answer with the job ended).
    assert job["state"] == "pending" and job["attempts"] == 0 and job["started"] is None

    seen = follow(server, job["id"])
    assert seen[-1]["state"] == "succeeded", seen[-1]["error"]
    # Run by the Celery worker that scripts/start started beside gunicorn, another process.
    pid = int(seen[-1]["worker"].split(":")[1].split("@")[0])
    assert "celery" in command_line(pid) and "worker" in command_line(pid)
    assert "gunicorn" not in command_line(pid)
    assert os.getpgid(pid) == os.getpgid(server.proc.pid)  # the quick start's own, stopped with it
    # Its messages went through the broker in files, under var/.
    assert (var / "broker" / "queue").is_dir()
    lines = [line["text"] for line in seen[-1]["log"]]
    assert lines[0].startswith("queued") and lines[-1] == "succeeded"


def group_processes(pgid: int) -> dict[int, str]:
    """The processes of the quick start's process group, with their command lines."""
    found = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if os.getpgid(int(entry.name)) == pgid:
                    found[int(entry.name)] = command_line(int(entry.name))
            except (OSError, ProcessLookupError):
                continue
    return found


def parent(pid: int) -> int:
    return int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])


def start_schedule(server, frames: int) -> dict:
    deadline = time.monotonic() + 180
    while True:  # the demo's own schedule, queued by load_demo, gives the application and the cluster
        status, schedules = request(server.port, "GET", "/api/v1/schedules/?limit=1", token=server.token)
        if schedules["results"]:
            break
        assert time.monotonic() < deadline, "the demo's schedule job did not run"
        time.sleep(0.5)
    demo = schedules["results"][0]
    body = {"algorithm": "heft", "cluster": demo["cluster"], "frames": frames}
    status, job = request(
        server.port, "POST", f"/api/v1/applications/{demo['application']}/schedule/", body, token=server.token
    )
    assert status == 202, job
    return job


def wait_job(server, job_id: str, until, timeout: float = 180) -> dict:
    deadline = time.monotonic() + timeout
    while True:
        status, job = request(server.port, "GET", f"/api/v1/jobs/{job_id}/", token=server.token)
        assert status == 200, job
        if until(job):
            return job
        assert time.monotonic() < deadline, f"job {job_id} is {job['state']} after {timeout} s"
        time.sleep(0.1)


def pid_of(job: dict) -> int:
    return int(job["worker"].split(":")[1].split("@")[0])


def test_one_long_job_does_not_block_the_others(quickstart):
    """Issue 30: a 0.09 s job waited 3 min 9 s behind a 5.5-minute one (one solo worker). Now the second job
    starts while the first runs, in another process of the pool (a solo worker starts it only after)."""
    server, _ = quickstart
    first = wait_job(server, start_schedule(server, 1000)["id"], lambda j: j["state"] != "pending")
    assert first["state"] == "running", first  # 1000 frames: seconds of work
    second = wait_job(server, start_schedule(server, 1)["id"], lambda j: j["state"] in ("succeeded", "failed"))
    assert second["state"] == "succeeded", second["error"]
    first = wait_job(server, first["id"], lambda j: j["state"] not in ("pending", "running"))
    assert first["state"] == "succeeded", first["error"]
    assert datetime.fromisoformat(second["started"]) < datetime.fromisoformat(first["finished"])
    assert pid_of(second) != pid_of(first)
    # The periodic sweeps have a worker of their own (with beat), beside the jobs' pool.
    commands = group_processes(os.getpgid(server.proc.pid)).values()
    assert any("sweeper@" in c and "-B" in c.split() for c in commands), commands


def test_a_worker_that_dies_is_started_again_and_the_web_server_keeps_serving(quickstart):
    """Issue 30: the worker died (kombu#1551) and scripts/start stopped the web server with it."""
    server, _ = quickstart
    pgid = os.getpgid(server.proc.pid)
    jobs = {pid for pid, c in group_processes(pgid).items() if "celery" in c and "jobs@" in c}
    [main] = [pid for pid in jobs if parent(pid) not in jobs]  # the pool's children are its children
    os.kill(main, signal.SIGKILL)
    status, _ = request(server.port, "GET", "/api/v1/jobs/", token=server.token)
    assert status == 200  # the web server did not go with it
    job = wait_job(server, start_schedule(server, 1)["id"], lambda j: j["state"] in ("succeeded", "failed"))
    assert job["state"] == "succeeded", job["error"]
    assert pid_of(job) != main and pid_of(job) in group_processes(pgid)
    assert "the jobs worker exited (status" in server.log()
    assert server.proc.poll() is None
