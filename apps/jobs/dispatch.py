"""Which job a worker runs next, and the messages that wake the workers up.

Fairness (issue 25): behind one fleet's 135 queued jobs, another fleet's 1-second job waited over 91 s, since
the broker's queue is first in, first out. So a job's message no longer names the job its worker runs: it is a
turn. The jobs wait in the database, and a worker given a turn takes the oldest pending job of the fleet served
least recently (the fleet whose last job started longest ago; a fleet never served first). A fleet's backlog
therefore delays another fleet's job by at most the run of the jobs already running, one per worker slot.

Every job still sends one message when it is recorded (:func:`publish`), so there are as many turns as jobs;
a turn that finds no pending job does nothing (a cancelled job's message, a message sent twice). A message
that is lost (a broker restarted empty, a file broker that could not write it, a broker down when the job
was recorded) leaves a job with no turn: :func:`resend_missing` compares the pending jobs with the messages
waiting in the queue and sends the missing ones. It runs in every worker's check thread and as a beat task.
"""

from __future__ import annotations

import logging
from datetime import datetime, timedelta

from django.conf import settings
from django.db.models import F, OuterRef, Q, Subquery
from django.utils import timezone

from . import joblog
from .models import Job

log = logging.getLogger(__name__)


def _queue() -> str:
    from continuum.celery import app

    return str(app.conf.task_default_queue)


def publish(job_id: str) -> bool:
    """Send a turn for ``job_id`` to the workers' queue; False (logged, and written in the job's log) when the
    broker refused it: the job stays pending and :func:`resend_missing` sends it once the broker is back, so
    whoever started the job is never answered with a 500 for the broker's sake."""
    from .tasks import run_job

    try:
        # No time limits in the message: the worker's own CONTINUUM_JOB_*_TIME_LIMIT apply (Celery would
        # otherwise send this process's settings along). The task id is the job's, so a cancel can revoke it.
        run_job.apply_async(args=(job_id,), task_id=job_id, time_limit=None, soft_time_limit=None)
    except Exception as exc:  # connection refused, broker full (ENOSPC), ...: the job waits in the database
        log.warning("job %s: its message was not sent (%s: %s); it is sent again once the broker takes it",
                    job_id, type(exc).__name__, exc)  # fmt: skip
        joblog.write(job_id, f"not queued yet: the broker refused the message ({type(exc).__name__}); "
                             "it is sent again once the broker takes it")  # fmt: skip
        return False
    return True


def next_job() -> Job | None:
    """The pending job a worker's turn runs: the oldest of the fleet served least recently (None: none)."""
    pending = Job.objects.filter(state=Job.State.PENDING)
    fleets = list(pending.order_by().values_list("fleet_id", flat=True).distinct()[:1000])
    if not fleets:
        return None
    from apps.tenancy.models import Fleet

    last_start = Job.objects.filter(fleet=OuterRef("pk"), started__isnull=False).order_by("-started")
    turn = (
        Fleet.objects.filter(pk__in=fleets)
        .annotate(served=Subquery(last_start.values("started")[:1]))
        .order_by(F("served").asc(nulls_first=True), "pk")
        .values_list("pk", flat=True)
        .first()
    )
    return pending.filter(fleet_id=turn).order_by("created", "pk").first()


def waiting_since(job: Job) -> datetime:
    return job.queued or job.created


def waiting_notice(job: Job, now: datetime | None = None) -> str:
    """What a pending job no worker has picked up within ``CONTINUUM_JOB_PICKUP_WARN_S`` says ('' otherwise)."""
    if job.state != Job.State.PENDING or job.created is None:
        return ""
    waited = ((now or timezone.now()) - waiting_since(job)).total_seconds()
    if waited < settings.CONTINUUM_JOB_PICKUP_WARN_S:
        return ""
    running = Job.objects.filter(state=Job.State.RUNNING).count()
    if not running:
        return (f"no worker has picked this job up in {waited:.0f} s and none is running a job: is a worker "
                "started, on this broker and queue?")  # fmt: skip
    ahead = Job.objects.filter(state=Job.State.PENDING, created__lt=job.created).count()
    return (f"waiting {waited:.0f} s for a worker: {running} job(s) running, {ahead} older job(s) pending "
            "(fleets take turns)")  # fmt: skip


def queued_messages() -> int:
    """Messages waiting in the workers' queue (not those a worker holds), as the broker counts them."""
    from continuum.celery import app

    with app.connection_for_read() as conn:
        conn.ensure_connection(max_retries=1)
        return int(conn.default_channel.queue_declare(queue=_queue(), passive=False).message_count)


def resend_missing(grace_s: float | None = None) -> int:
    """Send a turn for each pending job the queue holds no message for; how many were sent.

    Only jobs queued ``grace_s`` ago or more count (a job just recorded may not have sent its message yet), and
    their number is compared with the messages waiting: any surplus of jobs lost its messages. The oldest of
    them get the new ones, and their log says so.
    """
    if settings.CELERY_TASK_ALWAYS_EAGER:
        return 0
    grace_s = settings.CONTINUUM_JOB_RESEND_AFTER_S if grace_s is None else grace_s
    before = timezone.now() - timedelta(seconds=grace_s)
    waiting = Job.objects.filter(state=Job.State.PENDING).filter(
        Q(queued__lt=before) | Q(queued__isnull=True, created__lt=before)
    )
    need = waiting.count()
    if not need:
        return 0
    try:
        have = queued_messages()
    except Exception as exc:  # the broker is down: nothing can be sent now; the next round tries again
        log.warning("%d pending job(s): the broker cannot be asked for its queue (%s)", need, exc)
        return 0
    missing = need - have
    if missing <= 0:
        return 0
    sent = 0
    now = timezone.now()
    for job_id in waiting.order_by("created", "pk").values_list("pk", flat=True)[:missing]:
        # Stamped first: two checkers (a worker's thread, beat) do not both send for the same job.
        if (
            not Job.objects.filter(pk=job_id, state=Job.State.PENDING)
            .filter(Q(queued__lt=before) | Q(queued__isnull=True))
            .update(queued=now)
        ):
            continue
        joblog.write(job_id, f"the queue held {have} message(s) for {need} pending job(s): its message was "
                             "lost (broker restarted, or down when it was sent); sent again")  # fmt: skip
        if publish(str(job_id)):
            sent += 1
    if sent:
        log.warning("sent %d message(s) again: the queue held %d for %d pending job(s)", sent, have, need)
    return sent
