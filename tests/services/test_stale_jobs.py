"""A job whose worker is gone is noticed by its missing heartbeats, not after the broker's visibility timeout."""

import subprocess
import threading
from datetime import timedelta

import pytest
import redis
from django.db import connection
from django.utils import timezone

from apps.jobs.liveness import identity, lost_reason, recover_lost_jobs
from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.jobs.tasks import claim
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.models import Schedule

from .test_celery_worker import PLATFORM, make_app, wait_for

pytestmark = pytest.mark.services
TASKS = 20_000


@pytest.mark.django_db(transaction=True)
def test_worker_killed_mid_job_is_queued_again_long_before_the_visibility_timeout(fleet, start_worker):
    # Both workers keep the hour-long visibility timeout: Redis would not deliver the job again in time. The job
    # must still be running when its first heartbeat is seen: with 12,000 tasks and a 1 s beat it once ended
    # before its first beat; 20,000 tasks ran 2.0 s on a quiet machine, the first 0.25 s beat seen at 0.33 s.
    first = start_worker(visibility_timeout=3600, env={"CONTINUUM_JOB_HEARTBEAT_S": "0.25"})
    app = make_app(fleet, TASKS)
    job = start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft", "platform": PLATFORM})
    # The running job shows its worker's heartbeats.
    running = wait_for(job.pk, lambda j: j.state == Job.State.RUNNING and j.heartbeat and j.heartbeat > j.started)
    assert running.worker == identity(first.proc.pid)
    first.kill()
    assert Job.objects.get(pk=job.pk).state == Job.State.RUNNING  # interrupted, not finished
    # A new worker, no beat: the check thread every worker runs notices (beat's task does the same).
    start_worker(visibility_timeout=3600, env={"CONTINUUM_JOB_CHECK_S": "2"})
    # Noticed within a minute: queued again (and taken by the new worker), never left to the broker.
    job = wait_for(job.pk, lambda j: j.attempts > 1 or j.state != Job.State.RUNNING, timeout=60)
    assert job.interruption.startswith("worker lost: no heartbeat since "), job.interruption
    assert f"process {running.worker} is gone" in job.interruption
    job = wait_for(job.pk, lambda j: j.done, timeout=300)
    assert job.state == Job.State.SUCCEEDED, job.error
    assert job.attempts == 2
    assert Schedule.objects.filter(job=job).count() == 1
    assert Schedule.objects.get(job=job).assignments.count() == TASKS


def running_job(fleet, worker: str, silent_s: float, attempts: int = 1) -> Job:
    beat = timezone.now() - timedelta(seconds=silent_s)
    return Job.objects.create(
        fleet=fleet, kind="schedule", state=Job.State.RUNNING, worker=worker, heartbeat=beat, started=beat,
        attempts=attempts,
    )  # fmt: skip


@pytest.mark.django_db
def test_a_silent_worker_elsewhere_is_lost_a_beating_one_is_not(fleet, settings):
    settings.CONTINUUM_JOB_STALE_S = 30
    settings.CELERY_TASK_ALWAYS_EAGER = True  # no broker: nothing would run it again, so it fails
    silent = running_job(fleet, "robot-edge-7:4242@4026531836", silent_s=120)
    beating = running_job(fleet, "robot-edge-7:4243@4026531836", silent_s=2)
    legacy = running_job(fleet, "", silent_s=600)
    Job.objects.filter(pk=legacy.pk).update(heartbeat=None)  # a run from before heartbeats: not judged
    assert recover_lost_jobs() == [(str(silent.pk), "failed")]
    silent.refresh_from_db()
    assert silent.state == Job.State.FAILED and silent.finished is not None
    assert silent.error.startswith("worker lost: no heartbeat since ")
    assert "from robot-edge-7:4242@4026531836" in silent.error
    assert silent.interruption == silent.error
    for job in (beating, legacy):
        job.refresh_from_db()
        assert job.state == Job.State.RUNNING and not job.interruption


@pytest.mark.django_db
def test_celery_beat_runs_the_check(fleet, settings):
    from continuum.celery import app

    settings.CELERY_TASK_ALWAYS_EAGER = True
    entry = settings.CELERY_BEAT_SCHEDULE["jobs-recover-lost"]
    assert entry["schedule"] == settings.CONTINUUM_JOB_CHECK_S <= 15
    lost = running_job(fleet, "elsewhere:7@1", silent_s=300)
    assert app.tasks[entry["task"]].apply().get() == 1
    lost.refresh_from_db()
    assert lost.state == Job.State.FAILED and lost.error.startswith("worker lost: no heartbeat since ")


@pytest.mark.django_db(transaction=True)
def test_a_lost_job_is_queued_again_until_its_attempts_run_out(fleet, celery_broker, redis_url, settings):
    settings.CONTINUUM_JOB_MAX_ATTEMPTS = 3
    again = running_job(fleet, "elsewhere:1@1", silent_s=300, attempts=1)
    spent = running_job(fleet, "elsewhere:2@1", silent_s=300, attempts=3)
    assert sorted(recover_lost_jobs()) == sorted([(str(again.pk), "queued again"), (str(spent.pk), "failed")])
    again.refresh_from_db()
    spent.refresh_from_db()
    assert again.state == Job.State.PENDING and again.message.endswith("queued again")
    assert again.interruption.startswith("worker lost: no heartbeat since ")
    assert spent.state == Job.State.FAILED and spent.error.endswith("(attempt 3 of 3)")
    # The job is on its queue for a worker (one message: the lost run's own waits for the visibility timeout).
    assert redis.Redis.from_url(redis_url).llen(celery_broker) == 1
    assert recover_lost_jobs() == []  # judged once


@pytest.mark.django_db
def test_reading_a_job_whose_process_is_gone_fails_it(fleet, api, settings):
    settings.CELERY_TASK_ALWAYS_EAGER = True  # the quick start: jobs run inside the web process
    gone = subprocess.Popen(["sleep", "60"])
    gone.kill()
    gone.wait()
    worker = identity(gone.pid)
    job = running_job(fleet, worker, silent_s=0)
    Job.objects.filter(pk=job.pk).update(heartbeat=None)  # in-process runs send no heartbeats
    alive = running_job(fleet, identity(), silent_s=0)
    Job.objects.filter(pk=alive.pk).update(heartbeat=None)
    job.refresh_from_db()
    assert lost_reason(job) == f"worker lost: no heartbeat since its start, process {worker} is gone"
    assert lost_reason(alive) == ""
    body = api.get(f"/api/v1/jobs/{job.pk}/").json()
    assert body["state"] == "failed"
    assert body["error"] == body["interruption"] == lost_reason(job)
    assert api.get(f"/api/v1/jobs/{alive.pk}/").json()["state"] == "running"
    listed = {j["id"]: j["state"] for j in api.get("/api/v1/jobs/").json()["results"]}
    assert listed == {str(job.pk): "failed", str(alive.pk): "running"}


def claim_in_thread(job_id: str, out: list) -> threading.Thread:
    def run() -> None:
        try:
            out.append(claim(job_id, eager=False))
        finally:
            connection.close()

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return thread


@pytest.mark.django_db(transaction=True)
def test_a_second_delivery_waits_for_the_live_run_and_takes_over_a_lost_one(fleet, settings):
    settings.CONTINUUM_JOB_HEARTBEAT_S = 0.1  # how often the waiting delivery looks again
    live = running_job(fleet, identity(), silent_s=0)  # this very process runs it
    out: list = []
    waiting = claim_in_thread(str(live.pk), out)
    waiting.join(1.0)
    assert waiting.is_alive() and out == []  # not run a second time
    assert Job.objects.get(pk=live.pk).attempts == 1
    Job.objects.filter(pk=live.pk).update(state=Job.State.SUCCEEDED)
    waiting.join(30)
    assert out == [None]  # the live run finished it: nothing left to do

    gone = subprocess.Popen(["sleep", "60"])
    gone.kill()
    gone.wait()
    lost = running_job(fleet, identity(gone.pid), silent_s=0)
    assert claim(str(lost.pk), eager=False) == 2
    lost.refresh_from_db()
    assert lost.state == Job.State.RUNNING and lost.worker == identity() and lost.attempts == 2
    assert lost.interruption.endswith(f"process {identity(gone.pid)} is gone")
