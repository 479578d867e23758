"""The one Celery task that runs every job kind, with late acknowledgement so none is lost."""

import logging
import time
import uuid

from celery import shared_task
from django.utils import timezone

from apps.tenancy.audit import acting_for

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


@shared_task(bind=True, acks_late=True, reject_on_worker_lost=True, name="continuum.run_job")
def run_job(self, job_id: str) -> str:
    job = Job.objects.filter(pk=job_id).first()
    if job is None:
        log.warning("job %s no longer exists", job_id)
        return "missing"
    if job.done:  # a duplicate delivery of a finished job: nothing to do (idempotence)
        return job.state
    Job.objects.filter(pk=job.pk).update(
        state=Job.State.RUNNING, started=timezone.now(), attempts=job.attempts + 1, progress=0, error=""
    )
    last = [0.0]

    def progress(percent: float, message: str = "") -> None:
        now = time.monotonic()
        if now - last[0] < PROGRESS_INTERVAL and percent < 100:
            return
        last[0] = now
        Job.objects.filter(pk=job.pk).update(progress=max(0, min(100, int(percent))), message=message[:300])

    try:
        handler = HANDLERS[job.kind]
        job.refresh_from_db()
        # What the job changes is in the audit trail under whoever started it.
        with acting_for(job.created_by, job=str(job.pk), kind=job.kind):
            result, url = handler(job, progress)
    except Exception as exc:
        detail, result = failure(job, exc)
        Job.objects.filter(pk=job.pk).update(
            state=Job.State.FAILED, finished=timezone.now(), error=detail, message="failed", result=result
        )
        return Job.State.FAILED
    Job.objects.filter(pk=job.pk).update(
        state=Job.State.SUCCEEDED,
        finished=timezone.now(),
        progress=100,
        message="done",
        result=result,
        result_url=url,
    )
    return Job.State.SUCCEEDED
