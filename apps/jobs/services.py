"""Starting jobs: record the job, then hand it to Celery once the record is committed."""

from django.conf import settings
from django.db import transaction

from apps.tenancy.models import Fleet

from .models import Job
from .registry import JobKind, resolve


def start_job(kind: JobKind, fleet: Fleet, arguments: dict, user=None) -> Job:
    """Record a job of a registered ``kind`` and run it; an unregistered kind raises
    :class:`~apps.jobs.registry.UnknownJobKind` (a ``ValueError``) and records nothing."""
    kind_value = resolve(kind)
    job = Job.objects.create(
        kind=kind_value, fleet=fleet, arguments=arguments, created_by=user if user and user.is_authenticated else None
    )
    from .tasks import run_job

    if settings.CELERY_TASK_ALWAYS_EAGER:
        # The quick start (no broker) runs the job right here, in this process and transaction.
        run_job.apply(args=(str(job.pk),))
        job.refresh_from_db()
    else:
        # A worker may only see the job once its record is committed.
        # No time limits in the message: the worker's own CONTINUUM_JOB_*_TIME_LIMIT apply (Celery would
        # otherwise send this process's settings along, and the worker would obey them).
        transaction.on_commit(lambda: run_job.apply_async(args=(str(job.pk),), time_limit=None, soft_time_limit=None))
    return job
