"""The one Celery task that runs every job kind, with late acknowledgement so none is lost."""

import logging
import time
import traceback

from celery import shared_task
from django.utils import timezone

from .models import Job
from .registry import HANDLERS

log = logging.getLogger(__name__)
#: Minimum seconds between two progress writes, so a tight loop does not hammer the database.
PROGRESS_INTERVAL = 0.2


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
        result, url = handler(job, progress)
    except Exception as exc:
        log.info("job %s (%s) failed: %s", job.pk, job.kind, exc)
        detail = str(exc) if isinstance(exc, ValueError) else f"{type(exc).__name__}: {exc}"
        Job.objects.filter(pk=job.pk).update(
            state=Job.State.FAILED,
            finished=timezone.now(),
            error=detail,
            message="failed",
            result={"traceback": traceback.format_exc(limit=5)} if not isinstance(exc, ValueError) else None,
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
