"""The job page in a real browser (Chromium through Playwright) with a real worker: the bar moves without a
reload, and a job is cancelled and retried from its page."""

import re

import pytest

from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.models import Schedule
from tests.dashboard.test_browser import log_in
from tests.services.test_celery_worker import PLATFORM, make_app

pytestmark = [pytest.mark.browser, pytest.mark.services, pytest.mark.django_db(transaction=True)]

PERCENT = "Number(document.getElementById('job-percent').textContent)"
LONG_MS = 240_000


def schedule_job(fleet, app, user) -> Job:
    arguments = {"application": app.pk, "algorithm": "heft", "platform": PLATFORM}
    return start_job(SchedulingJob.SCHEDULE, fleet, arguments, user)


def test_progress_moves_without_a_reload(page, live_server, operator, fleet, start_worker):
    app = make_app(fleet, 20000)
    job = schedule_job(fleet, app, operator)  # queued: no worker yet
    log_in(page, live_server)
    page.goto(f"{live_server.url}/jobs/{job.pk}/")
    assert page.inner_text("#job-state") == "Pending" and page.inner_text("#job-percent") == "0"
    assert page.inner_text("#job-title").startswith("Schedule an application's DAG")
    assert page.get_attribute("#job-arguments a", "href") == f"/applications/{app.pk}/"
    assert page.locator("#job-retry").is_disabled() and "cancel it first" in page.inner_text("#job-retry-reason")
    page.evaluate("window.notReloaded = true")  # gone if the page reloads

    start_worker()
    page.wait_for_function(f"{PERCENT} > 0 && window.notReloaded === true", timeout=LONG_MS)
    first = int(page.inner_text("#job-percent"))
    assert page.inner_text("#job-state") == "Running"
    assert page.locator("#job-log li").count() >= 3  # queued, started, a step: the log follows too
    page.wait_for_function(f"{PERCENT} > {first} && window.notReloaded === true", timeout=LONG_MS)
    # At the end the page reloads once and links the result.
    page.wait_for_selector("#job-result", timeout=LONG_MS)
    schedule = Schedule.objects.get(job=job)
    assert page.get_attribute("#job-result", "href") == f"/schedules/{schedule.pk}/"
    assert page.locator("#job-cancel").is_disabled() and "succeeded" in page.inner_text("#job-cancel-reason")
    assert page.errors == []


def test_cancel_and_retry_from_the_job_page(page, live_server, operator, fleet, start_worker):
    start_worker()
    app = make_app(fleet, 20000)
    job = schedule_job(fleet, app, operator)
    log_in(page, live_server)
    page.goto(f"{live_server.url}/jobs/{job.pk}/")
    page.wait_for_selector("#job-state:has-text('Running')", timeout=LONG_MS)
    # Clicked again at once (as an impatient operator would): forms.js disabled the button on the first
    # submit, so one cancel reaches the server (a second would be refused with "cannot cancel ...").
    posts = []
    page.on("request", lambda req: posts.append(req.url) if req.method == "POST" else None)
    page.evaluate(
        "() => { const b = document.getElementById('job-cancel'); b.click();"
        " setTimeout(() => b.click(), 0); setTimeout(() => b.click(), 20); }"
    )
    page.wait_for_selector("#job-state:has-text('Cancelled')", timeout=LONG_MS)
    assert posts == [f"{live_server.url}/jobs/{job.pk}/cancel/"]
    assert "cannot cancel" not in page.content()
    assert "cancel asked by operator" in page.inner_text("#job-log")
    assert page.locator("#job-cancel").is_disabled()
    assert not Schedule.objects.filter(job=job).exists()

    page.click("#job-retry")
    page.wait_for_url(re.compile(r"/jobs/[0-9a-f-]+/$"))
    assert str(job.pk) not in page.url
    again = Job.objects.get(retry_of=job)
    assert page.url.endswith(f"/jobs/{again.pk}/")
    assert page.get_attribute("#job-retry-of", "href") == f"/jobs/{job.pk}/"
    assert again.arguments == job.arguments and again.created_by == operator
    page.wait_for_selector("#job-state:has-text('Running')", timeout=LONG_MS)
    page.click("#job-cancel")  # ends the test's worker early
    page.wait_for_selector("#job-state:has-text('Cancelled')", timeout=LONG_MS)
    assert page.errors == []
