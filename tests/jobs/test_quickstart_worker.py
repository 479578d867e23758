"""`scripts/start` runs jobs in a worker process of its own: a request that starts a job returns at once."""

import os
import time
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
