"""The job page and record without a worker (jobs in-process, as the suite asks): what the job was for, its
arguments linked to their rows, its bounded log, and the cancel/retry buttons with their reasons."""

import pytest

from apps.jobs import joblog
from apps.jobs.models import Job, JobLogLine
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from tests.services.test_celery_worker import PLATFORM, make_app

pytestmark = pytest.mark.django_db


def test_a_finished_job_says_what_it_was_for_and_what_happened(member, fleet, operator):
    app = make_app(fleet, 40)
    job = start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft", "platform": PLATFORM},
                    operator)  # fmt: skip
    assert job.state == Job.State.SUCCEEDED and job.duration is not None and job.duration >= 0
    texts = [line.text for line in joblog.lines(job.pk)]
    assert texts[0] == "queued by operator" and texts[1].startswith("attempt 1 started on ")
    assert texts[-1] == "succeeded" and len(texts) >= 4  # the handler's steps in between

    html = member.get(f"/jobs/{job.pk}/").content.decode()
    assert "Schedule an application&#x27;s DAG" in html
    assert f'href="/applications/{app.pk}/">{app.name}</a>' in html  # named, not "application 1" (issue 30)
    assert 'id="job-cancel" disabled title="the job has succeeded"' in html
    assert 'id="job-retry">Run again</button>' in html  # a succeeded job runs again (issue 30)
    assert "queued by operator" in html
    listed = member.get("/jobs/").content.decode()
    assert "Schedule an application&#x27;s DAG" in listed


def test_the_page_cancels_and_retries_and_refuses_with_the_reason(member, fleet, operator):
    app = make_app(fleet, 10)
    gpu_only = {"processors": [{"id": "g", "class": "gpu"}]}
    arguments = {"application": app.pk, "algorithm": "heft", "platform": gpu_only}
    queued = Job.objects.create(fleet=fleet, kind=SchedulingJob.SCHEDULE.value, arguments=arguments)
    response = member.post(f"/jobs/{queued.pk}/cancel/")
    assert response.status_code == 302 and response["Location"] == f"/jobs/{queued.pk}/"
    queued.refresh_from_db()
    assert queued.state == Job.State.CANCELLED and queued.attempts == 0
    again = member.post(f"/jobs/{queued.pk}/cancel/", follow=True).content.decode()
    assert "cannot cancel: the job has cancelled" in again

    response = member.post(f"/jobs/{queued.pk}/retry/")
    retry = Job.objects.get(retry_of=queued)
    assert response["Location"] == f"/jobs/{retry.pk}/"
    assert retry.arguments == arguments
    assert retry.state == Job.State.FAILED and "cannot run on any processor" in retry.error  # ran in-process
    assert member.get(f"/jobs/{queued.pk}/cancel/").status_code == 405  # POST only


def test_other_fleets_jobs_are_not_found(client, fleets, django_user_model):
    theirs = Job.objects.create(fleet=fleets[1], kind=SchedulingJob.SCHEDULE.value, arguments={})
    user = django_user_model.objects.create_user("alpha-only", password="alpha-pass-1234")
    fleets[0].members.add(user)
    client.force_login(user)
    for path in ("", "cancel/", "retry/"):
        method = client.get if not path else client.post
        assert method(f"/jobs/{theirs.pk}/{path}").status_code == 404
    theirs.refresh_from_db()
    assert theirs.state == Job.State.PENDING


def test_the_log_keeps_the_newest_lines_only(fleet):
    job = Job.objects.create(fleet=fleet, kind=SchedulingJob.SCHEDULE.value, arguments={})
    for i in range(joblog.LIMIT + 45):
        joblog.write(job.pk, f"step {i}", i % 100)
    joblog.prune(job.pk)
    kept = [line.text for line in joblog.lines(job.pk)]
    assert len(kept) == JobLogLine.objects.filter(job=job).count() == joblog.LIMIT
    assert kept[0] == "step 45" and kept[-1] == f"step {joblog.LIMIT + 44}"
    long = "x" * 1000
    joblog.write(job.pk, long)
    assert joblog.lines(job.pk)[-1].text == long[:300]


def test_a_job_no_worker_picks_up_within_a_minute_says_so_on_its_page_and_in_the_api(member, fleet, api):
    """Issue 30: a job queued where no worker consumes said "pending" for ever, with no warning."""
    from datetime import timedelta

    from django.utils import timezone

    long_ago = timezone.now() - timedelta(seconds=75)
    stuck = Job.objects.create(fleet=fleet, kind=SchedulingJob.SCHEDULE.value, queued=long_ago)
    fresh = Job.objects.create(fleet=fleet, kind=SchedulingJob.SCHEDULE.value, queued=timezone.now())
    body = api.get(f"/api/v1/jobs/{stuck.pk}/").json()
    assert body["state"] == "pending"
    assert body["waiting_notice"].startswith("no worker has picked this job up in 7")
    assert "is a worker started, on this broker and queue?" in body["waiting_notice"]
    assert api.get(f"/api/v1/jobs/{fresh.pk}/").json()["waiting_notice"] == ""
    html = member.get(f"/jobs/{stuck.pk}/").content.decode()
    assert 'id="job-waiting"' in html and "no worker has picked this job up in 7" in html
    assert 'id="job-waiting" hidden' in member.get(f"/jobs/{fresh.pk}/").content.decode()
    # Workers busy with other jobs: it says what is ahead of it.
    Job.objects.create(fleet=fleet, kind=SchedulingJob.SCHEDULE.value, state=Job.State.RUNNING,
                       worker="elsewhere:1@1", heartbeat=timezone.now())  # fmt: skip
    notice = api.get(f"/api/v1/jobs/{stuck.pk}/").json()["waiting_notice"]
    assert notice.startswith("waiting 7") and "1 job(s) running, 0 older job(s) pending (fleets take turns)" in notice
