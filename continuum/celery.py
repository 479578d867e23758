"""The Celery application. Workers: ``celery -A continuum worker``."""

import os
import time
from typing import Any

from celery import Celery
from celery.signals import beat_init, task_postrun, task_prerun, worker_process_shutdown, worker_ready

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


# ---- Metrics (README "Metrics"): tasks by name and outcome, and their durations, served on
# CONTINUUM_METRICS_PORT by the worker's main process; a prefork pool's children count into
# PROMETHEUS_MULTIPROC_DIR (continuum/metrics.py). ------------------------------------------------------------
_started: dict[str, float] = {}


_metrics: dict[str, Any] = {}


def _task_metrics() -> tuple[Any, Any]:
    """The task counters, made on first use (an eager task in the web process never makes them)."""
    if not _metrics:
        from prometheus_client import Counter, Histogram

        from continuum.metrics import DURATION_BUCKETS, PREFIX

        _metrics["tasks"] = Counter(
            f"{PREFIX}_celery_tasks", "Celery tasks finished, by task and state", ["task", "state"]
        )
        _metrics["seconds"] = Histogram(
            f"{PREFIX}_celery_task_duration_seconds", "Run time of Celery tasks", ["task"], buckets=DURATION_BUCKETS
        )
    return _metrics["tasks"], _metrics["seconds"]


@worker_ready.connect
def serve_worker_metrics(**_) -> None:
    from continuum.metrics import serve_from_env

    serve_from_env("celery worker")


@beat_init.connect
def serve_beat_metrics(**_) -> None:
    from continuum.metrics import serve_from_env

    serve_from_env("celery beat")


@task_prerun.connect
def _task_began(task_id=None, task=None, **_) -> None:
    if task_id is not None:
        _started[task_id] = time.perf_counter()


@task_postrun.connect
def _task_ended(task_id=None, task=None, state=None, **_) -> None:
    began = _started.pop(task_id, None) if task_id is not None else None
    if task is None or getattr(task.request, "is_eager", False):
        return  # run inside a web request or a command: not a worker's task
    tasks, seconds = _task_metrics()
    tasks.labels(task.name, str(state or "UNKNOWN").lower()).inc()
    if began is not None:
        seconds.labels(task.name).observe(time.perf_counter() - began)


@worker_process_shutdown.connect
def _child_gone(pid=None, **_) -> None:
    from continuum.metrics import multiprocess_dir

    if multiprocess_dir():
        from prometheus_client import multiprocess

        multiprocess.mark_process_dead(pid or os.getpid())
