"""The Celery application. Workers: ``celery -A continuum worker``."""

import os

from celery import Celery
from celery.signals import task_prerun, worker_ready

from continuum import filebroker  # noqa: F401 - registers the quick start's broker, continuumfs://

os.environ.setdefault("DJANGO_SETTINGS_MODULE", "continuum.settings")

app = Celery("continuum")
app.config_from_object("django.conf:settings", namespace="CELERY")
app.autodiscover_tasks()


@worker_ready.connect
def watch_for_lost_jobs(**_) -> None:
    """Every worker checks for jobs whose worker is gone (apps/jobs/liveness.py), busy slots or not."""
    from apps.jobs.liveness import watch

    watch()


@task_prerun.connect
def retire_old_connections(task=None, **_) -> None:
    """Before each task, what Django does before each request: close this thread's database connection if it is
    older than CONN_MAX_AGE or broke (CELERY_DB_REUSE_MAX keeps it across tasks otherwise). Not for a task run
    in-process (``apply``, ``CONTINUUM_JOBS_EAGER``): the connection is its caller's, maybe inside a transaction,
    and Celery's own Django fix-up leaves it alone too."""
    if task is not None and getattr(task.request, "is_eager", False):
        return
    from django.db import close_old_connections

    close_old_connections()
