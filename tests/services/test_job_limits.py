"""Jobs past the soft time limit fail with that reason, in a real worker process (the runner arms the limit
itself, so the solo pool the other service tests use has it too)."""

import pytest

from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob

from .test_celery_worker import PLATFORM, make_app, wait_for

pytestmark = [pytest.mark.services, pytest.mark.django_db(transaction=True)]


def long_job(fleet) -> Job:
    """A job far longer than a second: 100 pipelined frames of a 6,000-task DAG on 16 processors."""
    app = make_app(fleet, 6000)
    args = {"application": app.pk, "algorithm": "heft", "platform": PLATFORM, "params": {"frames": 100}}
    return start_job(SchedulingJob.SCHEDULE, fleet, args)


def test_a_job_past_the_soft_time_limit_fails_with_that_reason(fleet, start_worker):
    worker = start_worker(env={"CONTINUUM_JOB_SOFT_TIME_LIMIT": "1", "CONTINUUM_JOB_TIME_LIMIT": "60"})
    job = wait_for(long_job(fleet).pk, lambda j: j.done, timeout=120)
    assert job.state == Job.State.FAILED
    assert job.error == "time limit of 1 s exceeded"
    assert job.result is None and job.finished is not None
    assert worker.proc.poll() is None


def test_a_job_past_the_hard_time_limit_is_recorded_as_failed(fleet, start_worker):
    # Prefork: only a pool with child processes can kill a job; the worker's main process records it.
    # No soft limit (0): Celery never kills before the soft limit has passed.
    worker = start_worker(pool="prefork", env={"CONTINUUM_JOB_SOFT_TIME_LIMIT": "0", "CONTINUUM_JOB_TIME_LIMIT": "2"})
    job = wait_for(long_job(fleet).pk, lambda j: j.done, timeout=120)
    assert job.state == Job.State.FAILED
    assert job.error == "time limit of 2 s exceeded (the job was stopped)"
    assert worker.proc.poll() is None
