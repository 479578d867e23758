"""The fleet client against a running server (pytest-django's live_server): reports, events, ROS graphs from
recordings, schedule-and-wait with progress, jobs followed while they run, and the command line's exit codes."""

from __future__ import annotations

import json
import socket
import subprocess
import sys
import threading
import time
import uuid
from pathlib import Path

import pytest

from continuum.client.api.rosgraphs import rosgraphs_retrieve
from continuum.client.api.schedules import schedules_retrieve
from continuum.client.models import Job, RosGraph, Schedule
from continuum.fleet import ApiError, JobFailed, MissReport
from continuum.fleet.cli import main
from continuum.fleet.rosbag import rosgraph_from_bag

ROOT = Path(__file__).resolve().parents[2]
RESPONSE = "G(speed > 0 -> F[0,5000](arrived))"
#: tests/verification/test_api.py's run: the instance started at 10 s has no 'arrived' by 15 s.
RUN = [["speed", 3.0, 1000], ["arrived", False, 1000], ["arrived", True, 4000], ["speed", 0, 5000],
       ["arrived", False, 6000], ["speed", 5.0, 10000], ["speed", 0, 12000], ["speed", 0, 16000],
       ["speed", 0, 16500]]  # fmt: skip


@pytest.fixture
def monitor_of(api, cluster):
    """A monitor of ``text`` on the cluster's node0, made through the API."""

    def make(text: str, name: str = "m"):
        from apps.verification.models import Monitor

        a = api.post("/api/v1/assertions/", {"name": name, "text": text}, format="json")
        assert a.status_code == 201, a.data
        node = cluster.nodes.get(name="node0").pk
        m = api.post("/api/v1/monitors/", {"assertion": a.data["id"], "cluster": cluster.pk, "name": name,
                                           "node": node}, format="json")  # fmt: skip
        assert m.status_code == 201, m.data
        return Monitor.objects.get(pk=m.data["id"])

    return make


def cli(live_server, token, *args: str) -> list[str]:
    return ["--server", live_server.url, "--token", token, "--retries", "0", *args]


# ---- reports ---------------------------------------------------------------------------------------------
def test_report_is_stored_once_even_when_sent_again(fleet_client, cluster):
    from apps.realtime.models import MonitoringReport

    miss = time.time() - 0.2
    report = MissReport("node0", "slam", 2, 5, pod="slam-0", miss_at=miss)
    first = fleet_client.report_misses([report], cluster=cluster.pk)
    assert first[0]["stored"] == 1 and first[0]["duplicates"] == [] and first[0]["report_ids"] == [report.report_id]
    again = fleet_client.report_misses([report], cluster=cluster.pk)  # an answer lost, the batch sent again
    assert again[0]["stored"] == 0 and again[0]["duplicates"] == [0]
    row = MonitoringReport.objects.get(cluster=cluster, report_id=report.report_id)
    stored = (row.node, row.container_name, row.pod, row.missed_period, row.missed_total)
    assert stored == ("node0", "slam", "slam-0", 2, 5)
    assert row.miss_at.timestamp() == pytest.approx(miss, abs=1e-5) and row.sent_at is not None


def test_a_bad_report_is_refused_whole_with_the_reason(fleet_client, cluster):
    from apps.realtime.models import MonitoringReport

    good, bad = MissReport("node0", "slam", 1, 1), MissReport("node9", "slam", 1, 1)
    with pytest.raises(ApiError) as err:
        fleet_client.report_misses([good, bad], cluster=cluster.pk)
    assert err.value.status == 400 and "node9" in str(err.value) and "\n" not in str(err.value)
    assert not MonitoringReport.objects.exists()


# ---- events ----------------------------------------------------------------------------------------------
def test_events_in_batches_find_the_violation(fleet_client, cluster, monitor_of):
    monitor = monitor_of(RESPONSE)
    seen = []
    answers = fleet_client.post_events(cluster.pk, RUN, batch_size=2, on_batch=lambda n, a: seen.append(n))
    assert seen == [2, 4, 6, 8, 9] and all(a["routed"] == "in-process" for a in answers)
    found = [(v["instance_start"], v["time"]) for a in answers for v in a["violations"]]
    assert found == [(10000.0, 16000.0)]
    monitor.refresh_from_db()
    assert monitor.events == 9 and monitor.violation_count == 1


def test_events_of_a_recording_reach_the_monitors(fleet_client, cluster, monitor_of, robot_bag):
    from continuum.fleet.rosbag import events_from_bag

    monitor = monitor_of("G(speed.data < 8)", name="slow")
    events = events_from_bag(robot_bag, topics=["/speed"])
    # ``now`` (with the last batch) moves the clock past the last sample, which decides it
    answers = fleet_client.post_events(cluster.pk, events, batch_size=8, now=1001.0)
    assert len(answers) == 3
    times = [v["time"] for a in answers for v in a["violations"]]
    assert times == [800.0 + 50 * i for i in range(5)]  # speed.data = 0.5 i at 50 i ms: 8.0 from i = 16 on
    monitor.refresh_from_db()
    assert monitor.events == 21


# ---- ROS graphs -------------------------------------------------------------------------------------------
def test_rosgraph_of_a_recording_is_uploaded(fleet_client, robot_bag):
    doc = rosgraph_from_bag(robot_bag, publishers={"/scan": ["lidar"], "/speed": ["odom"]},
                            subscribers={"/scan": ["planner"], "/speed": ["planner"]})  # fmt: skip
    row = fleet_client.upload_rosgraph(doc, "run.json", name="run-1")
    assert isinstance(row, RosGraph) and row.name == "run-1"
    assert (row.node_count, row.topic_count) == (4, 3)
    back = rosgraphs_retrieve.sync(row.id, client=fleet_client.client)
    rates = {t["name"]: t["rate_hz"] for t in back.document["topics"]}
    assert rates == {"/arrived": 1.0, "/scan": 10.0, "/speed": 20.0}


def test_a_bad_graph_is_refused_with_its_fault(fleet_client):
    from apps.containers.models import RosGraph as Row

    bad = {"format": "continuum.rosgraph/v1", "topics": [{"name": "/x", "publishers": ["a"], "subscribers": [],
                                                          "rate_hz": -1, "msg_bytes": 8}]}  # fmt: skip
    with pytest.raises(ApiError) as err:
        fleet_client.upload_rosgraph(bad, "bad.json")
    assert err.value.status == 400 and str(err.value).startswith("upload ROS graph: HTTP 400: file: bad.json")
    assert not Row.objects.exists()


# ---- jobs -------------------------------------------------------------------------------------------------
def test_schedule_and_wait_with_progress(fleet_client, data_dir):
    app = fleet_client.upload_application((data_dir / "topcuoglu.dag.json").read_bytes(), "topcuoglu.dag.json")
    platform = json.loads((data_dir / "topcuoglu.platform.json").read_text())
    job = fleet_client.schedule(app.id, algorithm="heft", platform=platform)
    assert isinstance(job, Job) and job.kind == "schedule"
    seen = []
    done = fleet_client.wait(job.id, poll=0.05, on_progress=seen.append)
    assert done.state == "succeeded" and seen[-1].progress == 100 and done.result_url
    schedule = schedules_retrieve.sync(done.result["schedule"], client=fleet_client.client)
    assert isinstance(schedule, Schedule) and schedule.makespan == 80 and len(schedule.assignments) == 10


def test_wait_follows_a_running_job_to_its_end(fleet_client, fleet):
    """A job another process runs: the waiter sees each step of its progress, then the end."""
    from django.utils import timezone

    from apps.jobs.liveness import identity
    from apps.jobs.models import Job as Row

    row = Row.objects.create(kind="schedule", fleet=fleet, state="running", progress=10, message="placed 1/10",
                             worker=identity(), heartbeat=timezone.now())  # fmt: skip
    seen: list[tuple[str, int, str]] = []
    shown = threading.Condition()

    def progress(job: Job) -> None:
        with shown:
            seen.append((job.state, job.progress, job.message))
            shown.notify_all()

    def worker() -> None:  # advances only once the waiter has shown the previous step
        from django.db import connection

        try:
            for step, (state, pct, msg) in enumerate((("running", 60, "placed 6/10"), ("succeeded", 100, "done"))):
                with shown:
                    assert shown.wait_for(lambda n=step + 1: len(seen) >= n, timeout=60)
                Row.objects.filter(pk=row.pk).update(state=state, progress=pct, message=msg, heartbeat=timezone.now())
        finally:
            connection.close()

    t = threading.Thread(target=worker)
    t.start()
    done = fleet_client.wait(row.pk, poll=0.05, timeout=120, on_progress=progress)
    t.join()
    assert seen == [("running", 10, "placed 1/10"), ("running", 60, "placed 6/10"), ("succeeded", 100, "done")]
    assert done.state == "succeeded"


def test_a_failed_job_raises_with_its_error(fleet_client, fleet, live_server, token, capsys):
    from apps.jobs.models import Job as Row

    row = Row.objects.create(kind="push", fleet=fleet, state="failed", progress=40, error="node2 is NotReady")
    with pytest.raises(JobFailed, match="node2 is NotReady"):
        fleet_client.wait(row.pk)
    assert fleet_client.wait(row.pk, raise_on_failure=False).state == "failed"
    assert main(cli(live_server, token, "wait", str(row.pk))) == 1
    assert capsys.readouterr().err.strip().endswith("failed: node2 is NotReady")


# ---- the command line ---------------------------------------------------------------------------------------
def test_cli_report_and_bad_reports(live_server, token, cluster, capsys):
    args = ["--json", "report", "--node", "node1", "--container", "nav", "--missed-period", "3", "--missed-total",
            "3", "--cluster", str(cluster.pk), "--id", "nav-node1-0001"]  # fmt: skip
    assert main(cli(live_server, token, *args)) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["stored"] == 1 and out["report_ids"] == ["nav-node1-0001"]
    bad = [*args[:3], "node7", *args[4:]]
    assert main(cli(live_server, token, *bad)) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "node7" in err and err.startswith("error: report: HTTP 400")
    assert main(cli(live_server, token, "report", "--node", "n", "--container", "c", "--missed-period", "4",
                    "--missed-total", "3")) == 2  # fmt: skip
    assert capsys.readouterr().err == "error: need 0 <= --missed-period <= --missed-total\n"


def test_cli_streams_a_csv_and_refuses_a_bad_one_before_sending(live_server, token, cluster, monitor_of, tmp_path,
                                                                capsys):  # fmt: skip
    monitor = monitor_of(RESPONSE)
    bad = tmp_path / "bad.csv"
    bad.write_text("time,speed,arrived\n1000,3,false\n4000,,true\nlater,0,\n")
    assert main(cli(live_server, token, "events", str(bad), "--cluster", str(cluster.pk))) == 2
    assert capsys.readouterr().err == f"error: {bad}: line 4: time 'later' is not a number\n"
    monitor.refresh_from_db()
    assert monitor.events == 0  # nothing of the file was sent

    good = tmp_path / "run.csv"
    good.write_text("variable,value,timestamp\n" + "".join(f"{v},{str(x).lower()},{t}\n" for v, x, t in RUN))
    args = ["--json", "--progress", "events", str(good), "--cluster", str(cluster.pk), "--batch-size", "4"]
    assert main(cli(live_server, token, *args)) == 0
    captured = capsys.readouterr()
    out = json.loads(captured.out)
    assert out["events"] == 9 and out["violations"] == 1 and len(out["batches"]) == 3
    assert "9/9" in captured.err  # the progress bar reached the end
    monitor.refresh_from_db()
    assert monitor.events == 9 and monitor.violation_count == 1


def test_cli_bag_graph_upload_and_schedule_wait(live_server, token, robot_bag, data_dir, tmp_path, capsys):
    from apps.containers.models import RosGraph as Row

    names = tmp_path / "nodes.json"
    names.write_text(json.dumps({"publishers": {"/scan": ["lidar"]}, "subscribers": {"/scan": ["planner"]}}))
    assert main(cli(live_server, token, "--json", "bag-graph", str(robot_bag), "--nodes", str(names),
                    "--upload", "--name", "recorded")) == 0  # fmt: skip
    out = json.loads(capsys.readouterr().out)
    row = Row.objects.get(pk=out["id"])
    assert row.name == "recorded" and row.node_count == 4  # lidar, planner, speed_pub, arrived_pub

    assert main(cli(live_server, token, "--json", "upload", "application", str(data_dir / "topcuoglu.dag.json"))) == 0
    app = json.loads(capsys.readouterr().out)["id"]
    args = ["--json", "--progress", "schedule", str(app), "--platform", str(data_dir / "topcuoglu.platform.json"),
            "--wait", "--poll", "0.05"]  # fmt: skip
    assert main(cli(live_server, token, *args)) == 0
    captured = capsys.readouterr()
    job = json.loads(captured.out)
    assert job["state"] == "succeeded" and job["result_url"] and "100/100" in captured.err


@pytest.mark.parametrize(
    "argv, message",
    [
        (["wait", "not-a-job"], "error: 'not-a-job' is not a job id"),
        (["schedule", "0", "--cluster", "1"], "error: argument application: '0' must be positive"),
        (["upload", "rosgraph", "/nonexistent.json"], "error: /nonexistent.json: No such file or directory"),
        (["bag-events", "/nonexistent"], "error: /nonexistent: no such file or directory"),
        (["events", "x.csv", "--cluster", "1", "--batch-size", "20000"], "error: --batch-size must be at most 10000"),
    ],
)
def test_cli_bad_input_exits_2_with_one_line(live_server, token, argv, message, capsys):
    assert main(cli(live_server, token, *argv)) == 2
    assert capsys.readouterr().err == message + "\n"


def test_cli_server_refusals_and_failures(live_server, token, fleet, capsys):
    assert main(cli(live_server, token, "wait", str(uuid.uuid4()))) == 2  # another fleet's or no job: 404
    assert capsys.readouterr().err.startswith("error: job: HTTP 404")
    assert main(["--server", live_server.url, "--token", "wrong", "wait", str(uuid.uuid4())]) == 2
    assert "HTTP 401" in capsys.readouterr().err
    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    assert main(["--server", f"http://127.0.0.1:{port}", "--token", token, "--retries", "0",
                 "wait", str(uuid.uuid4())]) == 1  # fmt: skip
    assert capsys.readouterr().err.startswith("error: job: cannot reach http://127.0.0.1:")


def test_the_real_entry_point_without_a_token(tmp_path):
    env = {"PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT)}
    run = subprocess.run([sys.executable, "-m", "continuum.fleet", "--server", "http://127.0.0.1:9", "wait", "x"],
                         capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120)  # fmt: skip
    assert run.returncode == 2 and run.stdout == ""
    assert run.stderr == "error: give --server and --token (or CONTINUUM_SERVER and CONTINUUM_TOKEN)\n"
