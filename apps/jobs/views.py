"""Job pages: the list (by state) and one job's live progress, log and result, with its cancel and retry
buttons. Login required, fleet-scoped."""

from __future__ import annotations

from typing import Any

from django.contrib import messages
from django.contrib.auth.decorators import login_required
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, redirect, render
from django.views.decorators.http import require_POST

from apps.ui.helpers import paginate, scoped, search_term
from apps.ui.links import object_names, object_page, result_page

from . import joblog
from .models import Job
from .registry import kind_title
from .search import search_jobs, with_subject
from .services import JobActionRefused, cancel_job, retry_job


def job_result_link(job: Job) -> str:
    """Where a finished job's result is shown in the dashboard (its API URL when there is no page): the
    apps that own the pages register them (``apps.ui.links``)."""
    if job.state == Job.State.SUCCEEDED:
        page = result_page(job.result or {})
        if page is not None:
            return page
    return job.result_url


def argument_rows(arguments: dict[str, Any]) -> list[dict[str, Any]]:
    """A job's arguments as rows of (name, value, links): a row id (or a list of them) links to its page
    where its app registered one (``apps.ui.links.register_object_page``), named by the row's name where
    its app registered its model (``register_object_names``; "application 2" otherwise); documents are
    shown as JSON."""
    rows = []
    for name, value in (arguments or {}).items():
        values = value if isinstance(value, list) and value and len(value) <= 50 else [value]
        links = [(v, object_page(name, v)) for v in values]
        if all(url for _, url in links):
            names = object_names(name, values)
            labelled = [(v, url, names.get(v) or f"{name} {v}") for v, url in links]
            rows.append({"name": name, "links": labelled})
        else:
            rows.append({"name": name, "value": value, "document": isinstance(value, dict | list)})
    return rows


def _job(request: HttpRequest, pk) -> Job:
    return get_object_or_404(scoped(request, Job.objects.select_related("fleet", "created_by", "retry_of")), pk=pk)


@login_required
def job_list(request: HttpRequest) -> HttpResponse:
    # The list shows none of a job's JSON or text columns (a job's arguments may hold a platform document).
    jobs = scoped(request, Job.objects.select_related("fleet", "created_by")).defer("arguments", "result", "error")
    state = request.GET.get("state", "")
    if state in Job.State.values:
        jobs = jobs.filter(state=state)
    term = search_term(request)
    page = paginate(request, with_subject(search_jobs(jobs, term)))
    names = object_names("application", [j.subject_application for j in page])
    for job in page:
        job.application_name = names.get(_int(job.subject_application))
    return render(
        request,
        "jobs/job_list.html",
        {"page": page, "state": state, "states": Job.State.values, "search": term, "nav": "jobs"},
    )


def _int(value: Any) -> int | None:
    return int(value) if isinstance(value, str) and value.isdigit() else value if isinstance(value, int) else None


@login_required
def job_detail(request: HttpRequest, pk) -> HttpResponse:
    job = _job(request, pk)
    return render(
        request,
        "jobs/job_detail.html",
        {
            "job": job,
            "title": kind_title(job.kind),
            "arguments": argument_rows(job.arguments),
            "log": joblog.lines(job.pk),
            "retries": list(job.retries.order_by("created").values_list("pk", flat=True)),
            "result_link": job_result_link(job),
            "nav": "jobs",
        },
    )


@login_required
@require_POST
def job_cancel(request: HttpRequest, pk) -> HttpResponse:
    job = _job(request, pk)
    try:
        cancel_job(job, request.user)
    except JobActionRefused as exc:
        messages.error(request, str(exc))
    return redirect("jobs:job", pk=job.pk)


@login_required
@require_POST
def job_retry(request: HttpRequest, pk) -> HttpResponse:
    job = _job(request, pk)
    try:
        new = retry_job(job, request.user)
    except JobActionRefused as exc:
        messages.error(request, str(exc))
        return redirect("jobs:job", pk=job.pk)
    return redirect("jobs:job", pk=new.pk)
