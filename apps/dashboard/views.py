"""Operator dashboard: every page needs a login and shows only the user's fleets' objects (404 otherwise)."""

from __future__ import annotations

from django.contrib import messages
from django.contrib.auth.decorators import login_required
from django.core.paginator import Paginator
from django.db.models import Count, Q, QuerySet
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, redirect, render
from django.urls import reverse
from django.views.decorators.http import require_POST

from apps.clusters.models import Cluster, ComputeNode
from apps.jobs.models import Job
from apps.jobs.registry import HANDLERS
from apps.jobs.services import start_job
from apps.scheduling.models import Assignment, Schedule
from apps.tenancy.scoping import visible_fleets
from apps.workloads.models import Application
from continuum.engine.errors import InputError

from . import charts
from .forms import ScheduleForm, UploadForm

PAGE_SIZE = 25


def scoped(request: HttpRequest, qs: QuerySet, lookup: str = "fleet") -> QuerySet:
    """``qs`` limited to the fleets the user may see."""
    return qs.filter(**{f"{lookup}__in": visible_fleets(request)})


def paginate(request: HttpRequest, qs: QuerySet):
    return Paginator(qs, PAGE_SIZE).get_page(request.GET.get("page"))


def job_result_link(job: Job) -> str:
    """Where a finished job's result is shown in the dashboard (its API URL when there is no page)."""
    result = job.result or {}
    if job.state == Job.State.SUCCEEDED and isinstance(result.get("remap"), int):
        return reverse("heft4k:remap", args=[result["remap"]])
    if job.state == Job.State.SUCCEEDED and isinstance(result.get("schedule"), int):
        return reverse("dashboard:schedule", args=[result["schedule"]])
    if job.state == Job.State.SUCCEEDED and isinstance(result.get("page"), str) and result["page"].startswith("/"):
        return result["page"]  # the job names its dashboard page itself
    return job.result_url


# ---- home ---------------------------------------------------------------------------------------------
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


# ---- clusters -----------------------------------------------------------------------------------------
@login_required
def cluster_list(request: HttpRequest) -> HttpResponse:
    clusters = (
        scoped(request, Cluster.objects.select_related("fleet"))
        .annotate(
            node_count=Count("nodes", distinct=True),
            ready_count=Count("nodes", filter=Q(nodes__status="Ready"), distinct=True),
            link_count=Count("links", distinct=True),
        )
        .order_by("name", "pk")
    )
    return render(request, "dashboard/cluster_list.html", {"page": paginate(request, clusters), "nav": "clusters"})


@login_required
def cluster_detail(request: HttpRequest, pk: int) -> HttpResponse:
    cluster = get_object_or_404(scoped(request, Cluster.objects.select_related("fleet")), pk=pk)
    nodes = list(cluster.nodes.all())
    links = list(cluster.links.select_related("src", "dst"))
    figure = None
    if nodes:
        platform = cluster.to_platform(ready_only=False)
        fig = charts.network_figure(
            platform,
            status={n.name: n.status for n in nodes},
            bandwidth_scale=1000.0,  # the cluster platform stores Mbit per ms
            bandwidth_unit="Mbit/s",
            latency_unit="ms",
        )
        figure = charts.to_html(fig, div_id="network-chart")
    return render(
        request,
        "dashboard/cluster_detail.html",
        {
            "cluster": cluster,
            "nodes": nodes,
            "links": links,
            "figure": figure,
            "schedules": cluster.schedules.select_related("application")[:10],
            "nav": "clusters",
        },
    )


# ---- applications -------------------------------------------------------------------------------------
@login_required
def application_list(request: HttpRequest) -> HttpResponse:
    fleets = visible_fleets(request)
    bound = request.method == "POST"
    form = UploadForm(request.POST if bound else None, request.FILES if bound else None, fleets=fleets)
    status = 200
    if request.method == "POST":
        if form.is_valid():
            app = form.save(request.user)
            messages.success(request, f"Imported {app.name!r}: {app.task_count} tasks, {app.edge_count} edges.")
            return redirect("dashboard:application", pk=app.pk)
        status = 400
    apps = (
        scoped(request, Application.objects.select_related("fleet"))
        .annotate(schedule_count=Count("schedules"))
        .order_by("-created", "-pk")
    )
    return render(
        request,
        "dashboard/application_list.html",
        {"page": paginate(request, apps), "form": form, "has_fleet": fleets.exists(), "nav": "applications"},
        status=status,
    )


@login_required
def application_detail(request: HttpRequest, pk: int) -> HttpResponse:
    app = get_object_or_404(scoped(request, Application.objects.select_related("fleet")), pk=pk)
    return _application_page(request, app, ScheduleForm(application=app))


def _application_page(request: HttpRequest, app: Application, form: ScheduleForm, status: int = 200) -> HttpResponse:
    graph = app.graph
    return render(
        request,
        "dashboard/application_detail.html",
        {
            "app": app,
            "graph": graph,
            "figure": charts.to_html(charts.dag_figure(graph), div_id="dag-chart"),
            "form": form,
            "schedules": app.schedules.select_related("cluster")[:20],
            "remaps": app.remaps.select_related("schedule")[:10],
            "nav": "applications",
        },
        status=status,
    )


@login_required
@require_POST
def application_schedule(request: HttpRequest, pk: int) -> HttpResponse:
    app = get_object_or_404(scoped(request, Application.objects.select_related("fleet")), pk=pk)
    form = ScheduleForm(request.POST, application=app)
    if not form.is_valid():
        return _application_page(request, app, form, status=400)
    job = start_job("schedule", app.fleet, form.job_arguments(), request.user)
    return redirect("dashboard:job", pk=job.pk)


# ---- schedules ----------------------------------------------------------------------------------------
@login_required
def schedule_list(request: HttpRequest) -> HttpResponse:
    schedules = (
        scoped(request, Schedule.objects.select_related("fleet", "application", "cluster"))
        .annotate(task_count=Count("assignments"))
        .order_by("-created", "-pk")
    )
    return render(request, "dashboard/schedule_list.html", {"page": paginate(request, schedules), "nav": "schedules"})


@login_required
def schedule_detail(request: HttpRequest, pk: int) -> HttpResponse:
    schedule = get_object_or_404(
        scoped(request, Schedule.objects.select_related("fleet", "application", "cluster", "job")), pk=pk
    )
    return schedule_page(request, schedule)


def schedule_page(request: HttpRequest, schedule: Schedule, whatif_form=None, status: int = 200) -> HttpResponse:
    """The schedule page; HEFT4K schedules get their panel (apps.heft4k), with ``whatif_form`` when bound."""
    from apps.heft4k.views import schedule_panel

    rows = list(schedule.assignments.all())
    engine = schedule.to_engine()
    dag = schedule.application.graph
    critical: list[tuple[str, int]] = []
    figure = None
    problem = ""
    heft4k = None
    try:
        platform = schedule.engine_platform()
        critical = engine.critical_path(dag, platform)
        heft4k = schedule_panel(schedule, engine, platform, dag, critical, whatif_form)
        if heft4k is not None:
            figure = heft4k.pop("figure")
        else:
            fig = charts.gantt_figure(engine, platform=platform, dag=dag, critical=critical)
            figure = charts.to_html(fig, div_id="gantt-chart")
    except (InputError, KeyError) as exc:
        # The application's DAG changed since this schedule was made; draw what was stored.
        problem = f"the application changed since this schedule was made ({exc}); the critical path is not shown"
        nice = any(a.niceness is not None for a in engine.assignments)
        fig = charts.gantt_figure(engine, time_unit=dag.time_unit, colour_by_niceness=nice)
        figure = charts.to_html(fig, div_id="gantt-chart")
    on_path = set(critical)
    for row in rows:
        row.on_critical_path = (row.task, row.frame) in on_path
        row.duration = row.finish - row.start
    placement = [
        (value, label, sum(1 for r in rows if r.placement == value)) for value, label in Assignment.Placement.choices
    ]
    can_push = bool(schedule.cluster and schedule.cluster.kubeconfig)
    return render(
        request,
        "dashboard/schedule_detail.html",
        {
            "schedule": schedule,
            "rows": rows,
            "figure": figure,
            "problem": problem,
            "critical": critical,
            "critical_tasks": [t if len({r.frame for r in rows}) <= 1 else f"{t} [{f}]" for t, f in critical],
            "placement": placement,
            "can_push": can_push,
            "processor_count": len(schedule.platform.get("processors", [])),
            "has_niceness": any(r.niceness is not None for r in rows),
            "heft4k": heft4k,
            "nav": "schedules",
        },
        status=status,
    )


@login_required
@require_POST
def schedule_push(request: HttpRequest, pk: int) -> HttpResponse:
    schedule = get_object_or_404(scoped(request, Schedule.objects.select_related("fleet", "cluster")), pk=pk)
    if schedule.cluster is None or not schedule.cluster.kubeconfig:
        messages.error(request, "This schedule's cluster has no Kubernetes API configured: nothing to push to.")
        return redirect("dashboard:schedule", pk=schedule.pk)
    if "push_schedule" not in HANDLERS:
        messages.error(request, "Pushing to Kubernetes is not available in this installation.")
        return redirect("dashboard:schedule", pk=schedule.pk)
    job = start_job("push_schedule", schedule.fleet, {"schedule": schedule.pk}, request.user)
    return redirect("dashboard:job", pk=job.pk)


# ---- jobs ---------------------------------------------------------------------------------------------
@login_required
def job_list(request: HttpRequest) -> HttpResponse:
    jobs = scoped(request, Job.objects.select_related("fleet", "created_by"))
    state = request.GET.get("state", "")
    if state in Job.State.values:
        jobs = jobs.filter(state=state)
    return render(
        request,
        "dashboard/job_list.html",
        {"page": paginate(request, jobs), "state": state, "states": Job.State.values, "nav": "jobs"},
    )


@login_required
def job_detail(request: HttpRequest, pk) -> HttpResponse:
    job = get_object_or_404(scoped(request, Job.objects.select_related("fleet", "created_by")), pk=pk)
    return render(
        request,
        "dashboard/job_detail.html",
        {"job": job, "result_link": job_result_link(job), "nav": "jobs"},
    )
