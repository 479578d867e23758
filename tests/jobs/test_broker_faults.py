"""Faults of the broker (issue 25): Redis restarted empty under a running job and a queue of pending ones, and a
broker that is down when a job is started. Nothing may be lost, nobody may get a 500, no hand may be needed.

The restart is done on a redis-server of this test's own, on a free port (never the shared one)."""

import shutil
import socket
import subprocess
import time
import uuid
from pathlib import Path

import pytest
import redis

from apps.jobs.dispatch import resend_missing
from apps.jobs.models import Job
from apps.scheduling.models import Schedule
from tests.services.conftest import Worker, fresh_pools
from tests.services.test_celery_worker import PLATFORM, make_app, wait_for

from .test_fair_dispatch import schedule

pytestmark = [pytest.mark.services, pytest.mark.django_db(transaction=True)]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class RedisServer:
    """A redis-server of this test's own, in memory only: a restart starts it empty."""

    def __init__(self, port: int, workdir: Path):
        self.port, self.workdir, self.proc = port, workdir, None
        self.url = f"redis://127.0.0.1:{port}/0"

    def start(self) -> None:
        self.proc = subprocess.Popen(
            [shutil.which("redis-server") or "redis-server", "--port", str(self.port), "--bind", "127.0.0.1",
             "--save", "", "--appendonly", "no", "--dir", str(self.workdir)],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        )  # fmt: skip
        deadline = time.monotonic() + 20
        while True:
            try:
                redis.Redis.from_url(self.url, socket_connect_timeout=1).ping()
                return
            except redis.RedisError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.05)

    def kill(self) -> None:
        if self.proc and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(10)


@pytest.fixture
def own_redis(tmp_path, settings):
    """This test's Redis, and this process's Celery app publishing to it on a private queue."""
    from continuum.celery import app

    server = RedisServer(free_port(), tmp_path)
    server.start()
    queue = f"test-{uuid.uuid4().hex[:8]}"
    saved = {k: app.conf[k] for k in ("broker_url", "task_always_eager", "task_default_queue")}
    app.conf.update(broker_url=server.url, task_always_eager=False, task_default_queue=queue)
    fresh_pools()
    settings.CELERY_TASK_ALWAYS_EAGER = False
    yield server, queue
    app.conf.update(saved)
    fresh_pools()
    server.kill()


def test_a_worker_survives_redis_restarted_empty_and_nothing_is_lost(fleet, own_redis):
    server, queue = own_redis
    env = {"CONTINUUM_JOB_CHECK_S": "1", "CONTINUUM_JOB_RESEND_AFTER_S": "2"}
    worker = Worker(server.url, queue, visibility_timeout=3600, env=env)
    try:
        long = schedule(fleet, make_app(fleet, 6000))
        small = make_app(fleet, 20)
        queued = [schedule(fleet, small) for _ in range(3)]
        wait_for(long.pk, lambda j: j.state == Job.State.RUNNING)
        assert redis.Redis.from_url(server.url).llen(queue) == 3
        server.kill()
        time.sleep(8)  # down a while: the worker loses its connection and tries again (it once exited here)
        assert worker.proc.poll() is None, worker.log.read_text()[-3000:]
        server.start()  # empty: the three messages are gone, and the running job's unacknowledged one
        restarted = time.monotonic()
        assert redis.Redis.from_url(server.url).llen(queue) == 0
        jobs = [wait_for(j.pk, lambda j: j.done, timeout=180) for j in [long, *queued]]
        recovered = time.monotonic() - restarted
        for job in jobs:
            assert job.state == Job.State.SUCCEEDED and job.attempts == 1, (job.state, job.error)
        assert Schedule.objects.filter(job__in=jobs).count() == 4  # each ran once
        assert worker.proc.poll() is None, worker.log.read_text()[-3000:]  # it reconnected, it did not exit
        print(f"Redis restarted empty: 4 of 4 jobs succeeded once, {recovered:.1f} s after the restart")
        # And it still takes new work from the new Redis.
        after = schedule(fleet, small)
        assert wait_for(after.pk, lambda j: j.done, timeout=120).state == Job.State.SUCCEEDED
    finally:
        worker.stop()


def test_a_job_started_while_the_broker_is_down_waits_and_runs_once_it_is_back(fleet, own_redis, api):
    server, queue = own_redis
    server.kill()
    app = make_app(fleet, 20)
    response = api.post(f"/api/v1/applications/{app.pk}/schedule/", {"algorithm": "heft", "platform": PLATFORM},
                        format="json")  # fmt: skip
    assert response.status_code == 202, response.content[:500]
    job = Job.objects.get(pk=response.data["id"])
    assert job.state == Job.State.PENDING
    lines = [line.text for line in job.log_lines.all()]
    refused = "not queued yet: the broker refused the message (OperationalError)"
    assert any(line.startswith(refused) for line in lines), lines
    assert resend_missing(grace_s=0) == 0  # still down: nothing sent, nothing raised
    server.start()
    worker = Worker(server.url, queue, visibility_timeout=3600,
                    env={"CONTINUUM_JOB_CHECK_S": "1", "CONTINUUM_JOB_RESEND_AFTER_S": "1"})  # fmt: skip
    try:
        job = wait_for(job.pk, lambda j: j.done, timeout=120)
        assert job.state == Job.State.SUCCEEDED and job.attempts == 1, job.error
    finally:
        worker.stop()
