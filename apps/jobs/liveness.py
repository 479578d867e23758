"""Jobs whose worker is gone: who runs a job, its heartbeats, and the check that notices their absence.

The broker alone is slow to notice a dead worker: a job's message is acknowledged late (when the job ends),
and Redis redelivers an unacknowledged message only after the visibility timeout (an hour, since it must
exceed the longest job). Meanwhile the job would say ``running``. So a worker's run records its process
(``Job.worker``: host, pid and pid namespace) and stamps ``Job.heartbeat`` every
``CONTINUUM_JOB_HEARTBEAT_S`` from a thread. :func:`recover_lost_jobs` calls a run lost when its process on
this host is gone, or when it has been silent for ``CONTINUUM_JOB_STALE_S``, and queues the job again (or
fails it, after ``CONTINUUM_JOB_MAX_ATTEMPTS`` attempts or when there is no worker to queue it for) with
the reason. It runs every ``CONTINUUM_JOB_CHECK_S`` in a thread of every worker and as a Celery beat task,
and on job reads in the API.

A run is owned by its attempt number: writes of a run that lost the job (a worker that was only slow)
match no row, and the message the broker redelivers later finds the job done, or waits for the live run.
"""

from __future__ import annotations

import logging
import os
import re
import socket
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import datetime, timedelta
from functools import partial

from django.conf import settings
from django.db import DatabaseError, connection, transaction
from django.db.models import QuerySet
from django.utils import timezone

from . import joblog
from .models import Job

log = logging.getLogger(__name__)
WORKER = re.compile(r"^(?P<host>.+):(?P<pid>\d+)(?:@(?P<ns>\d+))?$")


def _pid_namespace() -> str:
    """The inode of this process's pid namespace ('' where /proc does not tell): pids are per namespace."""
    try:
        return re.sub(r"\D", "", os.readlink("/proc/self/ns/pid"))
    except OSError:
        return ""


def identity(pid: int | None = None) -> str:
    """This process (or another of this host and namespace), as ``Job.worker`` records it: host:pid@namespace."""
    ns = _pid_namespace()
    return f"{socket.gethostname()}:{pid or os.getpid()}" + (f"@{ns}" if ns else "")


def process_gone(worker: str) -> bool:
    """True when ``worker`` names a process of this host and pid namespace that no longer runs.

    False when it is alive or cannot be judged from here (another host or namespace): then only the
    heartbeat tells. A pid reused by another process also reads as alive, the safe side.
    """
    hit = WORKER.match(worker or "")
    if not hit or hit["host"] != socket.gethostname() or not hit["ns"] or hit["ns"] != _pid_namespace():
        return False
    pid = int(hit["pid"])
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except PermissionError:  # someone else's process: alive
        return False
    try:  # killed but not yet reaped by its parent: a zombie runs nothing
        return open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()[0] == "Z"
    except (OSError, IndexError):
        return False


def lost_reason(job: Job, now: datetime | None = None) -> str:
    """Why a ``running`` job's run is lost ('' when it is not, or cannot be told)."""
    if job.state != Job.State.RUNNING:
        return ""
    now = now or timezone.now()
    since = f"{job.heartbeat:%Y-%m-%d %H:%M:%S} UTC" if job.heartbeat else "its start"
    if job.worker and process_gone(job.worker):
        return f"worker lost: no heartbeat since {since}, process {job.worker} is gone"
    # A run without heartbeats is in-process (eager) or from before heartbeats: only its process tells.
    if job.heartbeat and now - job.heartbeat > timedelta(seconds=settings.CONTINUUM_JOB_STALE_S):
        return f"worker lost: no heartbeat since {since} from {job.worker or 'its worker'}"
    return ""


def recover_lost_jobs(queryset: QuerySet[Job] | None = None) -> list[tuple[str, str]]:
    """Queue again (or fail) every running job of ``queryset`` whose run is lost; [(job id, what happened)]."""
    now = timezone.now()
    eager = settings.CELERY_TASK_ALWAYS_EAGER
    done = []
    base = (Job.objects.all() if queryset is None else queryset).select_related(None)
    fields = ("id", "state", "worker", "heartbeat", "attempts", "cancel_requested")
    for job in base.filter(state=Job.State.RUNNING).only(*fields):
        reason = lost_reason(job, now)
        if not reason:
            continue
        # In-process runs (CONTINUUM_JOBS_EAGER): nothing would run it again. Or it lost its worker too often.
        again = not eager and job.attempts < settings.CONTINUUM_JOB_MAX_ATTEMPTS and not job.cancel_requested
        if job.cancel_requested:  # it was being cancelled: the cancel is what it gets
            change = {"state": Job.State.CANCELLED, "finished": now, "message": "cancelled (its worker was lost)"}
        elif again:
            change = {"state": Job.State.PENDING, "message": f"{reason}; queued again"[:300], "queued": now}
        else:
            tries = "" if eager else f" (attempt {job.attempts} of {settings.CONTINUUM_JOB_MAX_ATTEMPTS})"
            change = {"state": Job.State.FAILED, "finished": now, "message": "failed", "error": reason + tries}
        # Only if the run is still the one judged (no heartbeat or new attempt came in between).
        same_run = Job.objects.filter(pk=job.pk, state=Job.State.RUNNING, attempts=job.attempts,
                                      heartbeat=job.heartbeat, worker=job.worker)  # fmt: skip
        if not same_run.update(interruption=reason[:300], **change):
            continue
        outcome = "queued again" if again else str(change["state"])
        log.warning("job %s: %s; %s", job.pk, reason, outcome)
        joblog.write(job.pk, f"{reason}; {outcome}")
        if again:
            from .dispatch import publish

            transaction.on_commit(partial(publish, str(job.pk)))
        done.append((str(job.pk), outcome))
    return done


@contextmanager
def heartbeats(job_id, attempt: int, interval: float | None = None) -> Iterator[None]:
    """Stamp the job's heartbeat every ``interval`` seconds from a thread while the body runs."""
    interval = settings.CONTINUUM_JOB_HEARTBEAT_S if interval is None else interval
    stop = threading.Event()

    def beat() -> None:
        try:
            while not stop.wait(interval):
                try:
                    mine = Job.objects.filter(pk=job_id, attempts=attempt, state=Job.State.RUNNING)
                    if not mine.update(heartbeat=timezone.now()):
                        return  # the job is no longer this run's (finished, or taken over)
                except DatabaseError as exc:  # the next beat may get through; silence is judged, not this
                    log.warning("job %s: heartbeat not recorded: %s", job_id, exc)
                    connection.close()
        finally:
            connection.close()  # this thread's own connection

    thread = threading.Thread(target=beat, name=f"job-heartbeat-{job_id}", daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join(timeout=30)


def watch(interval: float | None = None) -> threading.Thread:
    """Run :func:`recover_lost_jobs` every ``interval`` seconds in a daemon thread of this process.

    Every worker runs one (continuum/celery.py): a check sent by beat waits in the queue behind the jobs
    when every worker slot is busy, this thread does not.
    """
    interval = settings.CONTINUUM_JOB_CHECK_S if interval is None else interval

    def loop() -> None:
        while True:
            time.sleep(interval)
            try:
                recover_lost_jobs()
                from .dispatch import resend_missing

                resend_missing()
            except Exception:  # the next round may succeed (database restarting, ...)
                log.exception("checking for jobs whose worker is gone or whose message is lost")
            finally:
                connection.close()  # not held across a fork of the worker's pool

    thread = threading.Thread(target=loop, name="jobs-lost-worker-check", daemon=True)
    thread.start()
    return thread
