"""Starting, cancelling and retrying jobs: record the job, then hand it to Celery once the record is committed."""

from __future__ import annotations

import logging
from functools import partial

from django.conf import settings
from django.db import transaction
from django.utils import timezone

from apps.tenancy.models import Fleet

from . import joblog
from .dispatch import publish
from .models import Job
from .registry import JobKind, resolve

log = logging.getLogger(__name__)


class JobActionRefused(ValueError):
    """A cancel or retry that does not apply to the job as it is (the message says why)."""


def _who(user) -> str:
    return f" by {user}" if user is not None and getattr(user, "is_authenticated", False) else ""


def start_job(kind: JobKind | str, fleet: Fleet, arguments: dict, user=None, *, retry_of: Job | None = None) -> Job:
    """Record a job of a registered ``kind`` and run it; an unregistered kind raises
    :class:`~apps.jobs.registry.UnknownJobKind` (a ``ValueError``) and records nothing."""
    kind_value = resolve(kind)
    job = Job.objects.create(
        queued=timezone.now(),
        kind=kind_value,
        fleet=fleet,
        arguments=arguments,
        created_by=user if user and user.is_authenticated else None,
        retry_of=retry_of,
    )
    joblog.write(job.pk, f"queued{_who(user)}" + (f" as a retry of job {retry_of.pk}" if retry_of else ""), 0)
    from .tasks import run_job

    if settings.CELERY_TASK_ALWAYS_EAGER:
        # Only when asked (CONTINUUM_JOBS_EAGER: the tests): the job runs right here, in this transaction.
        run_job.apply(args=(str(job.pk),), task_id=str(job.pk))
        job.refresh_from_db()
    else:
        # A worker may only see the job once its record is committed. A broker that refuses the message (down,
        # full) leaves the job pending, said in its log, and it is sent again later (apps/jobs/dispatch.py).
        transaction.on_commit(partial(publish, str(job.pk)))
    return job


def cancel_job(job: Job, user=None) -> Job:
    """Cancel ``job``: a queued job ends ``cancelled`` at once (its message is revoked, and a run that gets it
    anyway finds the job ended); a running one is asked to stop and ends ``cancelled`` at its next step
    (its progress callback raises :class:`~apps.jobs.tasks.JobCancelled`). :class:`JobActionRefused` for a
    job that has ended or is already being cancelled."""
    now = timezone.now()
    with transaction.atomic():  # the change and its log line together
        queued = Job.objects.filter(pk=job.pk, state=Job.State.PENDING).update(
            state=Job.State.CANCELLED, finished=now, cancel_requested=now, message="cancelled before it started"
        )
        if queued:
            joblog.write(job.pk, f"cancelled{_who(user)} before it started")
            if not settings.CELERY_TASK_ALWAYS_EAGER:
                transaction.on_commit(lambda: _revoke(str(job.pk)))
        elif Job.objects.filter(pk=job.pk, state=Job.State.RUNNING, cancel_requested__isnull=True).update(
            cancel_requested=now, message="cancelling: the job stops at its next step"
        ):
            joblog.write(job.pk, f"cancel asked{_who(user)}: the job stops at its next step")
        else:
            job.refresh_from_db()
            raise JobActionRefused(f"cannot cancel: {job.cancel_unavailable() or 'the job has ended'}")
    job.refresh_from_db()
    return job


def retry_job(job: Job, user=None) -> Job:
    """A new job of the same kind, fleet and arguments as the failed or cancelled ``job`` (whose rows its
    handler looks up again within the fleet, as for any job); :class:`JobActionRefused` for any other job."""
    reason = job.retry_unavailable()
    if reason:
        raise JobActionRefused(f"cannot retry: {reason}")
    with transaction.atomic():
        new = start_job(job.kind, job.fleet, dict(job.arguments or {}), user, retry_of=job)
        joblog.write(job.pk, f"retried{_who(user)} as job {new.pk}")
    return new


def _revoke(task_id: str) -> None:
    """Tell the workers to drop a queued job's message (best effort: the run would find the job ended anyway)."""
    from continuum.celery import app

    try:
        app.control.revoke(task_id)
    except Exception as exc:  # the broker unreachable: the cancelled state already stops the run
        log.warning("job %s: revoke not sent: %s", task_id, exc)
