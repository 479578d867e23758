"""The one Celery task that runs every job kind, with late acknowledgement so none is lost."""

import logging
import signal
import threading
import time
import traceback
from collections.abc import Iterator
from contextlib import contextmanager

from celery import shared_task, signals
from celery.exceptions import SoftTimeLimitExceeded, TimeLimitExceeded
from django.conf import settings
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
        with soft_time_limit(settings.CELERY_TASK_SOFT_TIME_LIMIT, enabled=not self.request.is_eager):
            result, url = handler(job, progress)
    except SoftTimeLimitExceeded:
        # Celery's soft limit (CELERY_TASK_SOFT_TIME_LIMIT): the job is over, with that reason; no
        # traceback, since nothing in the job was wrong but its size.
        _fail(job.pk, time_limit_message(settings.CELERY_TASK_SOFT_TIME_LIMIT))
        return Job.State.FAILED
    except MemoryError:
        # The worker child's address-space limit (CONTINUUM_JOB_MEMORY_LIMIT_MIB).
        _fail(job.pk, f"memory limit of {settings.CONTINUUM_JOB_MEMORY_LIMIT_MIB} MiB exceeded")
        return Job.State.FAILED
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


@contextmanager
def soft_time_limit(seconds: float, enabled: bool = True) -> Iterator[None]:
    """Raise SoftTimeLimitExceeded in the job after ``seconds``, in whatever pool runs it (Celery enforces
    its soft limit only in prefork children; the solo pool and a worker's main thread get it here).
    Only in a worker's main thread: never in a web process running a job eagerly."""
    usable = enabled and seconds > 0 and hasattr(signal, "SIGALRM")
    if not usable or threading.current_thread() is not threading.main_thread():
        yield
        return

    def expire(signum, frame):
        raise SoftTimeLimitExceeded(seconds)

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def time_limit_message(seconds: float) -> str:
    return f"time limit of {seconds:g} s exceeded"


def _fail(job_id, error: str) -> None:
    Job.objects.filter(pk=job_id).exclude(state__in=[Job.State.SUCCEEDED, Job.State.FAILED]).update(
        state=Job.State.FAILED, finished=timezone.now(), error=error, message="failed", result=None
    )


@signals.task_failure.connect
def _on_hard_time_limit(sender=None, task_id=None, exception=None, args=None, **_: object) -> None:
    """The hard limit kills the worker child; the worker's main process then records the job as failed
    (otherwise it would stay "running" for ever)."""
    if getattr(sender, "name", None) != run_job.name or not isinstance(exception, TimeLimitExceeded):
        return
    if args:
        limit = exception.args[0] if exception.args else settings.CELERY_TASK_TIME_LIMIT
        _fail(args[0], time_limit_message(float(limit)) + " (the job was stopped)")


@signals.worker_process_init.connect
def _limit_child_memory(**_: object) -> None:
    """Cap each prefork child's address space, so a job that grows past it fails with MemoryError (recorded
    as "memory limit of N MiB exceeded") instead of taking the machine; ``worker_max_memory_per_child``
    then replaces children that stay large."""
    mib = settings.CONTINUUM_JOB_MEMORY_LIMIT_MIB
    if mib > 0:
        import resource

        _, hard = resource.getrlimit(resource.RLIMIT_AS)
        soft = mib * 1024 * 1024 if hard == resource.RLIM_INFINITY else min(mib * 1024 * 1024, hard)
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
