"""Search on the schedules, comparisons and jobs lists, page and API alike (issue 30: ``search=`` was silently
ignored), and jobs an operator can find (issue 30, item 11): list rows with the application and algorithm, a
job page naming its application, a succeeded job run again (same arguments, a new job)."""

import pytest
from django.urls import reverse

from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.models import Comparison, Schedule
from tests.conftest import make_application

pytestmark = pytest.mark.django_db

PLATFORM = {"processors": [{"id": "p0"}, {"id": "p1"}]}


@pytest.fixture
def two_apps(fleet):
    """Two applications, each scheduled once in-process (no broker in the tests): HEFT on one, XEFT on the other."""
    first = make_application(fleet)
    first.name = "lidar-pipeline"
    first.save()
    second = make_application(fleet)
    second.name = "arm-control"
    second.save()
    jobs = {}
    for app, algorithm in ((first, "heft"), (second, "xeft")):
        args = {"application": app.pk, "algorithm": algorithm, "platform": PLATFORM}
        jobs[app.name] = start_job(SchedulingJob.SCHEDULE, fleet, args)
        assert jobs[app.name].state == "succeeded", jobs[app.name].error
    return first, second, jobs


def shown_schedules(page) -> set[int]:
    return {s.pk for s in page.context["page"]}


def test_search_filters_the_schedules_list_and_api(member, api, two_apps):
    first, second, _ = two_apps
    lidar = Schedule.objects.get(application=first)
    page = member.get(reverse("scheduling:schedules") + "?search=LIDAR")
    assert shown_schedules(page) == {lidar.pk}
    assert 'value="LIDAR"' in page.content.decode()  # the box keeps the search
    assert shown_schedules(member.get(reverse("scheduling:schedules") + "?search=xeft")) == {
        Schedule.objects.get(application=second).pk
    }
    assert shown_schedules(member.get(reverse("scheduling:schedules") + "?search=nothing-like-it")) == set()
    assert {r["id"] for r in api.get("/api/v1/schedules/?search=lidar").data["results"]} == {lidar.pk}
    assert len(api.get("/api/v1/schedules/?search=").data["results"]) == 2


def test_search_filters_the_comparisons_list_and_api(member, api, fleet, two_apps):
    first, second, _ = two_apps
    kept = Comparison.objects.create(
        fleet=fleet, application=first, platform=PLATFORM, algorithms=["heft"], best="heft", result={}
    )
    Comparison.objects.create(
        fleet=fleet, application=second, platform=PLATFORM, algorithms=["xeft"], best="xeft", result={}
    )
    page = member.get(reverse("scheduling:comparisons") + "?search=lidar")
    assert {c.pk for c in page.context["page"]} == {kept.pk}
    assert {r["id"] for r in api.get("/api/v1/comparisons/?search=lidar").data["results"]} == {kept.pk}


def test_search_filters_the_jobs_list_and_api_by_application_and_algorithm(member, api, two_apps):
    _, _, jobs = two_apps
    lidar = jobs["lidar-pipeline"]
    for term in ("lidar", "heft", "lidar heft"):
        page = member.get(reverse("jobs:jobs") + f"?search={term}")
        assert [j.pk for j in page.context["page"]] == [lidar.pk], term
        assert [r["id"] for r in api.get(f"/api/v1/jobs/?search={term}").data["results"]] == [str(lidar.pk)], term
    assert list(member.get(reverse("jobs:jobs") + "?search=lidar+xeft").context["page"]) == []
    # The state filter and the search together, and the links keep both.
    page = member.get(reverse("jobs:jobs") + "?state=succeeded&search=arm")
    assert [j.pk for j in page.context["page"]] == [jobs["arm-control"].pk]
    assert "?state=failed&amp;search=arm" in page.content.decode()


def test_job_rows_show_the_application_and_algorithm_and_the_job_page_names_it(member, two_apps):
    first, _, jobs = two_apps
    body = member.get(reverse("jobs:jobs")).content.decode()
    row = body[body.index(str(jobs["lidar-pipeline"].pk)[:8]) :].split("</tr>")[0]
    assert f'href="{reverse("workloads:application", args=[first.pk])}">lidar-pipeline</a>' in row
    assert ">HEFT</td>" in row
    page = member.get(reverse("jobs:job", args=[jobs["lidar-pipeline"].pk])).content.decode()
    assert f'<a href="{reverse("workloads:application", args=[first.pk])}">lidar-pipeline</a>' in page
    assert f"application {first.pk}<" not in page


def test_a_succeeded_job_runs_again_as_a_new_job_with_the_same_arguments(member, two_apps):
    _, _, jobs = two_apps
    done = jobs["lidar-pipeline"]
    page = member.get(reverse("jobs:job", args=[done.pk])).content.decode()
    assert 'id="job-retry">Run again</button>' in page
    response = member.post(reverse("jobs:job-retry", args=[done.pk]))
    again = Job.objects.exclude(pk__in=[j.pk for j in jobs.values()]).get()
    assert response.status_code == 302 and response["Location"] == reverse("jobs:job", args=[again.pk])
    assert again.retry_of_id == done.pk and again.arguments == done.arguments and again.kind == done.kind
    assert again.state == "succeeded" and again.result["schedule"] != done.result["schedule"]
    assert Job.objects.get(pk=done.pk).state == "succeeded"
