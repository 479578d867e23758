"""The home page: what the user's fleets hold and their recent jobs. It sits above every domain app (each
owns its pages: clusters, workloads, scheduling, devices, jobs...) and is the only page that reads them all."""

from __future__ import annotations

from django.contrib.auth.decorators import login_required
from django.http import HttpRequest, HttpResponse
from django.shortcuts import render

from apps.clusters.models import Cluster, ComputeNode
from apps.jobs.models import Job
from apps.scheduling.models import Schedule
from apps.tenancy.scoping import visible_fleets
from apps.ui.helpers import scoped
from apps.workloads.models import Application


@login_required
def home(request: HttpRequest) -> HttpResponse:
    jobs = scoped(request, Job.objects.select_related("fleet", "created_by"))
    counts = {
        "clusters": scoped(request, Cluster.objects).count(),
        "nodes": scoped(request, ComputeNode.objects, "cluster__fleet").count(),
        "nodes_ready": scoped(request, ComputeNode.objects, "cluster__fleet").filter(status="Ready").count(),
        "applications": scoped(request, Application.objects).count(),
        "schedules": scoped(request, Schedule.objects).count(),
        "jobs_active": jobs.filter(state__in=[Job.State.PENDING, Job.State.RUNNING]).count(),
        "jobs_failed": jobs.filter(state=Job.State.FAILED).count(),
    }
    return render(
        request,
        "dashboard/home.html",
        {"counts": counts, "recent_jobs": jobs[:10], "fleets": visible_fleets(request), "nav": "home"},
    )
