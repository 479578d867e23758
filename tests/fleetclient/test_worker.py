"""Schedule and wait through the client while a real Celery worker process runs the job (real Redis): the
waiter sees the job queued, running with partial progress, then done."""

from __future__ import annotations

import pytest

from continuum.client.api.schedules import schedules_retrieve
from tests.services.conftest import celery_broker, redis_url, start_worker  # noqa: F401
from tests.services.test_celery_worker import PLATFORM, make_app

pytestmark = [pytest.mark.services]


def test_schedule_and_wait_while_a_worker_runs_it(fleet_client, fleet, start_worker):  # noqa: F811
    start_worker()
    app = make_app(fleet, 6000)
    job = fleet_client.schedule(app.pk, algorithm="heft", platform=PLATFORM)
    assert job.state == "pending"  # queued for the worker, not run in the web request
    seen = []
    done = fleet_client.wait(job, poll=0.02, timeout=300, on_progress=lambda j: seen.append((j.state, j.progress)))
    assert done.state == "succeeded", done.error
    assert any(state == "running" and 0 < pct < 100 for state, pct in seen), seen
    assert [pct for _, pct in seen] == sorted(pct for _, pct in seen)  # progress never goes back
    schedule = schedules_retrieve.sync(done.result["schedule"], client=fleet_client.client)
    assert schedule.assignment_count == 6000 and schedule.makespan == done.result["makespan"]
    assert len(schedule.assignments) == 1000 and not schedule.assignments_complete  # the detail stays bounded
    every = list(fleet_client.assignments(schedule.id))
    assert len(every) == 6000 and len({(a.task, a.frame) for a in every}) == 6000
