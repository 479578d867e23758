"""Cancel and retry, through the API, with a real Celery worker process (Redis, the test database)."""

import pytest

from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.models import Schedule
from tests.services.test_celery_worker import PLATFORM, make_app, wait_for

pytestmark = [pytest.mark.services, pytest.mark.django_db(transaction=True)]


def schedule_job(fleet, app) -> Job:
    return start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft", "platform": PLATFORM})


def log_text(job: Job) -> str:
    return "\n".join(job.log_lines.values_list("text", flat=True))


def test_cancel_a_running_job_stops_it_at_its_next_step_and_stores_nothing(fleet, api, start_worker):
    worker = start_worker()
    app = make_app(fleet, 20000)
    job = schedule_job(fleet, app)
    wait_for(job.pk, lambda j: j.state == Job.State.RUNNING and j.progress > 0)

    response = api.post(f"/api/v1/jobs/{job.pk}/cancel/")
    assert response.status_code == 200, response.data
    assert response.data["cancel_requested"] is not None
    assert response.data["cancel_unavailable"]  # a second cancel would be refused, and says why
    assert api.post(f"/api/v1/jobs/{job.pk}/cancel/").status_code == 409

    job = wait_for(job.pk, lambda j: j.done, timeout=300)
    assert job.state == Job.State.CANCELLED, (job.state, job.error)
    assert job.progress < 100 and job.result is None
    assert not Schedule.objects.filter(job=job).exists()  # stopped before it stored anything
    text = log_text(job)
    assert "cancel asked" in text and "cancelled at the step" in text
    # The worker carries on with the next job.
    small = schedule_job(fleet, make_app(fleet, 50))
    assert wait_for(small.pk, lambda j: j.done).state == Job.State.SUCCEEDED
    assert worker.proc.poll() is None


def test_cancel_a_queued_job_before_any_worker_runs_it(fleet, api, start_worker):
    app = make_app(fleet, 50)
    queued = schedule_job(fleet, app)
    response = api.post(f"/api/v1/jobs/{queued.pk}/cancel/")
    assert response.status_code == 200 and response.data["state"] == "cancelled"
    assert response.data["retry_unavailable"] == ""

    start_worker()  # the queued message is delivered now (or was revoked): the job stays cancelled
    after = schedule_job(fleet, app)  # one worker slot, first in first out: once this one ran, so had that one
    assert wait_for(after.pk, lambda j: j.done).state == Job.State.SUCCEEDED
    queued.refresh_from_db()
    assert queued.state == Job.State.CANCELLED and queued.attempts == 0 and queued.started is None
    assert not Schedule.objects.filter(job=queued).exists()


def test_retry_runs_a_cancelled_or_failed_job_again_with_its_arguments(fleet, api, other_api, start_worker):
    start_worker()
    app = make_app(fleet, 50)
    bad = start_job(
        SchedulingJob.SCHEDULE,
        fleet,
        {"application": app.pk, "algorithm": "heft", "platform": {"processors": [{"id": "g", "class": "gpu"}]}},
    )
    bad = wait_for(bad.pk, lambda j: j.done)
    assert bad.state == Job.State.FAILED

    # Another fleet cannot see it, so cannot retry it either.
    assert other_api.post(f"/api/v1/jobs/{bad.pk}/retry/").status_code == 404
    response = api.post(f"/api/v1/jobs/{bad.pk}/retry/")
    assert response.status_code == 202, response.data
    again = Job.objects.get(pk=response.data["id"])
    assert again.pk != bad.pk and again.retry_of_id == bad.pk and response.data["retry_of"] == bad.pk
    assert again.arguments == bad.arguments and again.fleet == bad.fleet and again.kind == bad.kind
    again = wait_for(again.pk, lambda j: j.done)
    assert again.state == Job.State.FAILED and again.error == bad.error  # same arguments, same answer
    assert "retried by" in log_text(bad) and str(again.pk) in log_text(bad)

    good = schedule_job(fleet, app)
    good = wait_for(good.pk, lambda j: j.done)
    refused = api.post(f"/api/v1/jobs/{good.pk}/cancel/")
    assert refused.status_code == 409 and "succeeded" in refused.data["detail"]
    # A succeeded job runs again (issue 30): a new job, same arguments, the original untouched.
    rerun = api.post(f"/api/v1/jobs/{good.pk}/retry/")
    assert rerun.status_code == 202, rerun.data
    again = wait_for(rerun.data["id"], lambda j: j.done)
    assert again.pk != good.pk and again.retry_of_id == good.pk and again.arguments == good.arguments
    assert again.state == Job.State.SUCCEEDED and again.result["schedule"] != good.result["schedule"]
    assert Job.objects.get(pk=good.pk).state == Job.State.SUCCEEDED
