"""The one Celery task that runs every job kind, with late acknowledgement so none is lost.

Delivery is at least once: the message is acknowledged when the job ends, so a worker that dies leaves it
to be delivered again (after the broker's visibility timeout), and the stale-job check
(:mod:`apps.jobs.liveness`) queues a lost job again within a minute. A run therefore first claims the job
(its attempt number); a delivery of a job another live run holds waits for that run instead of running
the job twice.
"""

import logging
import time
import uuid
from contextlib import nullcontext

from celery import shared_task
from django.conf import settings
from django.utils import timezone

from apps.tenancy.audit import acting_for

from .liveness import heartbeats, identity, lost_reason, recover_lost_jobs
from .models import Job
from .registry import HANDLERS

log = logging.getLogger(__name__)
#: Minimum seconds between two progress writes, so a tight loop does not hammer the database.
PROGRESS_INTERVAL = 0.2


def failure(job: Job, exc: Exception) -> tuple[str, dict | None]:
    """What a failed job tells its callers: the message of an input error (ValueError, InputError, KubeError:
    the caller's to fix), else one line with an error id; the traceback goes to the log under that id only,
    since it names files and internals the caller has no business seeing."""
    if isinstance(exc, ValueError):
        log.info("job %s (%s) failed: %s", job.pk, job.kind, exc)
        return str(exc), None
    error_id = str(uuid.uuid4())
    log.error("job %s (%s) failed: internal error %s", job.pk, job.kind, error_id, exc_info=exc)
    return f"internal error ({type(exc).__name__}); error id {error_id}", {"error_id": error_id}


def claim(job_id: str, eager: bool) -> int | None:
    """Take the job for this process: its attempt number, or None when it is gone or finished."""
    waited = False
    while True:
        job = Job.objects.filter(pk=job_id).first()
        if job is None or job.done:
            return None
        if job.state == Job.State.RUNNING and not lost_reason(job):
            # A second delivery while a live run holds the job (it ran past the visibility timeout).
            if not waited:
                log.info("job %s is running on %s: waiting for that run", job_id, job.worker)
                waited = True
            time.sleep(min(5.0, settings.CONTINUUM_JOB_HEARTBEAT_S))
            continue
        interruption = {}
        if job.state == Job.State.RUNNING:  # a lost run, noticed by this delivery first
            interruption = {"interruption": lost_reason(job)[:300]}
        now = timezone.now()
        taken = Job.objects.filter(pk=job.pk, state=job.state, attempts=job.attempts).update(
            state=Job.State.RUNNING,
            started=now,
            attempts=job.attempts + 1,
            progress=0,
            error="",
            worker=identity(),
            # In-process runs send no heartbeats (their caller's transaction may hold the row): none expected.
            heartbeat=None if eager else now,
            **interruption,
        )
        if taken:
            return job.attempts + 1


@shared_task(bind=True, acks_late=True, reject_on_worker_lost=True, name="continuum.run_job")
def run_job(self, job_id: str) -> str:
    eager = bool(self.request.is_eager)
    attempt = claim(job_id, eager)
    if attempt is None:  # deleted, or a duplicate delivery of a finished job: nothing to do (idempotence)
        job = Job.objects.filter(pk=job_id).first()
        return job.state if job else "missing"
    mine = Job.objects.filter(pk=job_id, attempts=attempt, state=Job.State.RUNNING)
    last = [0.0]

    def progress(percent: float, message: str = "") -> None:
        now = time.monotonic()
        if now - last[0] < PROGRESS_INTERVAL and percent < 100:
            return
        last[0] = now
        mine.update(progress=max(0, min(100, int(percent))), message=message[:300])

    job = Job.objects.get(pk=job_id)
    beating = nullcontext() if eager else heartbeats(job_id, attempt)
    try:
        with beating:
            handler = HANDLERS[job.kind]
            # What the job changes is in the audit trail under whoever started it.
            with acting_for(job.created_by, job=str(job.pk), kind=job.kind):
                result, url = handler(job, progress)
    except Exception as exc:
        detail, result = failure(job, exc)
        mine.update(
            state=Job.State.FAILED, finished=timezone.now(), error=detail, message="failed", result=result
        )
        return Job.State.FAILED
    if not mine.update(
        state=Job.State.SUCCEEDED,
        finished=timezone.now(),
        progress=100,
        message="done",
        result=result,
        result_url=url,
    ):
        log.warning("job %s: attempt %s ended after the job was taken from it; result dropped", job_id, attempt)
    return Job.State.SUCCEEDED


@shared_task(name="continuum.recover_lost_jobs")
def recover_lost_jobs_task() -> int:
    """Celery beat: queue again (or fail) running jobs whose worker is gone (see apps.jobs.liveness)."""
    return len(recover_lost_jobs())
