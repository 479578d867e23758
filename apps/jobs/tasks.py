"""The one Celery task that runs every job kind, with late acknowledgement so none is lost.

A message is a turn (:mod:`apps.jobs.dispatch`): the worker that gets it takes the pending job whose fleet's
turn it is, by its attempt number, so a job runs once however many messages name it. Delivery is at least
once: the message is acknowledged when the job ends, so a worker that dies leaves it to be delivered again
(after the broker's visibility timeout), and the stale-job check (:mod:`apps.jobs.liveness`) queues a lost
job again within a minute. In-process (eager) runs claim the job the message names; a claim of a job another
live run holds waits for that run instead of running the job twice.
"""

import logging
import signal
import threading
import time
import uuid
from collections.abc import Iterator
from contextlib import contextmanager, nullcontext

from celery import shared_task, signals
from celery.exceptions import SoftTimeLimitExceeded, TimeLimitExceeded
from django.conf import settings
from django.db import transaction
from django.utils import timezone

from apps.tenancy.audit import acting_for

from . import joblog
from .dispatch import next_job, resend_missing
from .liveness import heartbeats, identity, lost_reason, recover_lost_jobs
from .models import Job
from .registry import HANDLERS

log = logging.getLogger(__name__)
#: Minimum seconds between two progress writes, so a tight loop does not hammer the database.
PROGRESS_INTERVAL = 0.2


class JobCancelled(BaseException):
    """Raised in a job's run by its progress callback once a cancel was asked: the handler stops at that step.
    A BaseException, like asyncio's CancelledError, so a handler's ``except Exception`` does not swallow it."""


def failure(job: Job, exc: Exception) -> tuple[str, dict | None]:
    """What a failed job tells its callers: the message of an input error (ValueError, InputError, KubeError:
    the caller's to fix), else one line with an error id; the traceback goes to the log under that id only,
    since it names files and internals the caller has no business seeing. A job stopped by its size (the soft
    time limit, the worker child's memory cap) says which limit, with no traceback: nothing in it was wrong."""
    if isinstance(exc, SoftTimeLimitExceeded):
        return time_limit_message(settings.CELERY_TASK_SOFT_TIME_LIMIT), None
    if isinstance(exc, MemoryError):
        return f"memory limit of {settings.CONTINUUM_JOB_MEMORY_LIMIT_MIB} MiB exceeded", None
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
            joblog.write(job.pk, f"attempt {job.attempts + 1} started on {identity()}", 0)
            return job.attempts + 1


def take_turn() -> tuple[str, int] | None:
    """Take the next job by the fair dispatch (:func:`apps.jobs.dispatch.next_job`) for this process: its id and
    attempt number, or None when no job is pending."""
    while True:
        job = next_job()
        if job is None:
            return None
        now = timezone.now()
        # Taken only if still as read: another worker's turn may have taken it meanwhile (then look again).
        if Job.objects.filter(pk=job.pk, state=Job.State.PENDING, attempts=job.attempts).update(
            state=Job.State.RUNNING, started=now, attempts=job.attempts + 1, progress=0, error="",
            worker=identity(), heartbeat=now,
        ):  # fmt: skip
            joblog.write(job.pk, f"attempt {job.attempts + 1} started on {identity()}", 0)
            return str(job.pk), job.attempts + 1


@shared_task(bind=True, acks_late=True, reject_on_worker_lost=True, name="continuum.run_job")
def run_job(self, job_id: str) -> str:
    """A worker's turn (apps/jobs/dispatch.py): it runs the pending job whose fleet's turn it is, which may not be
    ``job_id``; in-process (``CONTINUUM_JOBS_EAGER``) it runs ``job_id`` itself."""
    eager = bool(self.request.is_eager)
    if eager:
        attempt = claim(job_id, eager)
    else:
        turn = take_turn()
        job_id, attempt = turn if turn else (job_id, None)
    if attempt is None:  # deleted, finished, or no job left for this turn: nothing to do (idempotence)
        job = Job.objects.filter(pk=job_id).first()
        return job.state if job else "missing"
    return run_attempt(job_id, attempt, eager)


def run_attempt(job_id: str, attempt: int, eager: bool) -> str:
    """Run the job's handler as the attempt this process holds, and record how it ended."""
    mine = Job.objects.filter(pk=job_id, attempts=attempt, state=Job.State.RUNNING)
    last = [0.0]
    logged = [""]

    def progress(percent: float, message: str = "") -> None:
        """Record progress, and stop the job here (JobCancelled) when a cancel was asked: a step boundary, so
        nothing after the cancel is half done. A new message is also a line of the job's log."""
        now = time.monotonic()
        if now - last[0] < PROGRESS_INTERVAL and percent < 100:
            return
        last[0] = now
        if not mine.filter(cancel_requested__isnull=True).update(
            progress=max(0, min(100, int(percent))), message=message[:300]
        ):
            if mine.filter(cancel_requested__isnull=False).exists():
                raise JobCancelled(message)
            return  # the job was taken from this run (lost, then queued again): its writes are not recorded
        if message and message != logged[0]:
            logged[0] = message
            joblog.write(job_id, message, percent)

    job = Job.objects.get(pk=job_id)
    beating = nullcontext() if eager else heartbeats(job_id, attempt)
    try:
        with beating:
            handler = HANDLERS[job.kind]
            # What the job changes is in the audit trail under whoever started it.
            with (
                acting_for(job.created_by, job=str(job.pk), kind=job.kind),
                soft_time_limit(settings.CELERY_TASK_SOFT_TIME_LIMIT, enabled=not eager),
            ):
                result, url = handler(job, progress)
    except JobCancelled as stop:
        end(mine, job_id, f"cancelled at the step {str(stop)!r}: nothing after it ran",
            state=Job.State.CANCELLED, message="cancelled")  # fmt: skip
        return Job.State.CANCELLED
    except Exception as exc:
        detail, result = failure(job, exc)
        end(mine, job_id, f"failed: {detail}", state=Job.State.FAILED, error=detail, message="failed", result=result)
        return Job.State.FAILED
    late = Job.objects.filter(pk=job_id, cancel_requested__isnull=False).exists()
    line = "succeeded" + (" (its last step ran before the cancel came)" if late else "")
    if not end(mine, job_id, line, state=Job.State.SUCCEEDED, progress=100, message="done", result=result,
               result_url=url):  # fmt: skip
        log.warning("job %s: attempt %s ended after the job was taken from it; result dropped", job_id, attempt)
    return Job.State.SUCCEEDED


def end(mine, job_id, line: str, **change) -> bool:
    """Record the end of this run (``change``) with its log line, together, if the job is still the run's."""
    with transaction.atomic():
        ended = bool(mine.update(finished=timezone.now(), **change))
        if ended:
            joblog.write(job_id, line, change.get("progress"))
    joblog.prune(job_id)
    return ended


@shared_task(name="continuum.recover_lost_jobs")
def recover_lost_jobs_task() -> int:
    """Celery beat: queue again (or fail) running jobs whose worker is gone (see apps.jobs.liveness), and send
    the messages of pending jobs the queue lost (apps.jobs.dispatch)."""
    return len(recover_lost_jobs()) + resend_missing()


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
    unfinished = Job.objects.filter(pk=job_id).exclude(state__in=Job.FINAL)
    end(unfinished, job_id, f"failed: {error}", state=Job.State.FAILED, error=error, message="failed", result=None)


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
