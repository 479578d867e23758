"""Fleets take turns (issue 25): one fleet's backlog delays another fleet's job by at most the job already running,
and a pending job whose message the broker lost is sent again by the workers' own check."""

import pytest
import redis

from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.models import Schedule
from tests.services.test_celery_worker import PLATFORM, make_app, wait_for

pytestmark = [pytest.mark.services, pytest.mark.django_db(transaction=True)]


def schedule(fleet, app) -> Job:
    return start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft", "platform": PLATFORM})


def test_another_fleets_job_runs_next_not_after_the_backlog(fleets, start_worker):
    alpha, beta = fleets
    start_worker()  # one slot: the strictest case
    big = make_app(alpha, 3000)
    backlog = [schedule(alpha, big) for _ in range(6)]
    # Beta's one short job comes while Alpha's first is running and five more wait (FIFO: it ran seventh).
    wait_for(backlog[0].pk, lambda j: j.state != Job.State.PENDING, timeout=120)
    late = schedule(beta, make_app(beta, 20))
    late = wait_for(late.pk, lambda j: j.done, timeout=300)
    assert late.state == Job.State.SUCCEEDED, late.error
    before = Job.objects.filter(fleet=alpha, started__lt=late.started).count()
    assert before == 1, f"{before} of Alpha's jobs started before Beta's"
    # Alpha's backlog still runs, every job once, in its order.
    for job in backlog:
        job = wait_for(job.pk, lambda j: j.done, timeout=300)
        assert job.state == Job.State.SUCCEEDED and job.attempts == 1, job.error
    started = list(Job.objects.filter(fleet=alpha).order_by("started").values_list("pk", flat=True))
    assert started == [j.pk for j in backlog]
    assert Schedule.objects.filter(job__in=backlog).count() == 6


def test_pending_jobs_whose_messages_are_lost_are_sent_again(fleet, celery_broker, redis_url, start_worker):
    app = make_app(fleet, 20)
    jobs = [schedule(fleet, app) for _ in range(4)]
    conn = redis.Redis.from_url(redis_url)
    sent = conn.llen(celery_broker)
    conn.delete(celery_broker)  # what a broker restarted empty leaves: the jobs say pending, nothing runs them
    assert sent == 4, [line.text for line in jobs[0].log_lines.all()]
    Job.objects.filter(pk__in=[j.pk for j in jobs]).update(queued=None)  # sent long ago
    start_worker(env={"CONTINUUM_JOB_CHECK_S": "1", "CONTINUUM_JOB_RESEND_AFTER_S": "1"})
    for job in jobs:
        job = wait_for(job.pk, lambda j: j.done, timeout=120)
        assert job.state == Job.State.SUCCEEDED and job.attempts == 1, job.error
        lines = [line.text for line in job.log_lines.all()]
        assert any("its message was lost" in line and line.endswith("sent again") for line in lines), lines
    assert Schedule.objects.filter(job__in=jobs).count() == 4
