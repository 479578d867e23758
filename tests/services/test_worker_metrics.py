"""A real Celery worker serves /metrics on CONTINUUM_METRICS_PORT: its tasks by name and state, counted in its
prefork children (PROMETHEUS_MULTIPROC_DIR) and summed by the main process's scrape."""

from __future__ import annotations

import pytest

from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from tests.kubeapi import free_port
from tests.scrape import scrape_until, total
from tests.services.test_celery_worker import PLATFORM, make_app, wait_for

pytestmark = [pytest.mark.services, pytest.mark.django_db(transaction=True)]
TASK = "continuum.run_job"


@pytest.mark.parametrize("pool", ["solo", "prefork"])
def test_a_worker_counts_its_tasks(fleet, start_worker, tmp_path, pool):
    port = free_port()
    env = {"CONTINUUM_METRICS_PORT": str(port)}
    if pool == "prefork":
        env["PROMETHEUS_MULTIPROC_DIR"] = str(tmp_path)
    start_worker(pool=pool, env=env)
    url = f"http://127.0.0.1:{port}/metrics"
    scrape_until(url, lambda f: True, what="the worker's metrics")
    app = make_app(fleet, 20)
    jobs = [
        start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft", "platform": PLATFORM})
        for _ in range(2)
    ]
    for job in jobs:
        assert wait_for(job.pk, lambda j: j.state != Job.State.PENDING and j.state != Job.State.RUNNING).state == (
            Job.State.SUCCEEDED
        )
    families = scrape_until(
        url, lambda f: total(f, "continuum_celery_tasks_total", task=TASK, state="success") >= 2, what="2 tasks"
    )
    assert total(families, "continuum_celery_task_duration_seconds_count", task=TASK) >= 2
