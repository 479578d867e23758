"""Job pages: the list (by state) and one job's live progress and result. Login required, fleet-scoped."""

from __future__ import annotations

from django.contrib.auth.decorators import login_required
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, render

from apps.ui.helpers import paginate, scoped
from apps.ui.links import result_page

from .models import Job


def job_result_link(job: Job) -> str:
    """Where a finished job's result is shown in the dashboard (its API URL when there is no page): the
    apps that own the pages register them (``apps.ui.links``)."""
    if job.state == Job.State.SUCCEEDED:
        page = result_page(job.result or {})
        if page is not None:
            return page
    return job.result_url


@login_required
def job_list(request: HttpRequest) -> HttpResponse:
    # The list shows none of a job's JSON or text columns (a job's arguments may hold a platform document).
    jobs = scoped(request, Job.objects.select_related("fleet", "created_by")).defer("arguments", "result", "error")
    state = request.GET.get("state", "")
    if state in Job.State.values:
        jobs = jobs.filter(state=state)
    return render(
        request,
        "jobs/job_list.html",
        {"page": paginate(request, jobs), "state": state, "states": Job.State.values, "nav": "jobs"},
    )


@login_required
def job_detail(request: HttpRequest, pk) -> HttpResponse:
    job = get_object_or_404(scoped(request, Job.objects.select_related("fleet", "created_by")), pk=pk)
    return render(
        request,
        "jobs/job_detail.html",
        {"job": job, "result_link": job_result_link(job), "nav": "jobs"},
    )
