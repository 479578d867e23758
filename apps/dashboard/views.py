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
from apps.devices.api import advice
from apps.devices.forms import AdviceForm
from apps.devices.models import DeviceProfile
from apps.devices.serializers import AdviceRequestSerializer
from apps.jobs.models import Job
from apps.jobs.registry import HANDLERS
from apps.jobs.services import start_job
from apps.scheduling.forms import CompareForm, ScheduleForm
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.models import Assignment, Comparison, Schedule
from apps.tenancy.scoping import visible_fleets
from apps.workloads.forms import GenerateForm, UploadForm
from apps.workloads.models import Application
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform

from . import charts

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
    if job.state == Job.State.SUCCEEDED and isinstance(result.get("comparison"), int):
        return reverse("dashboard:comparison", args=[result["comparison"]])
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
    if bound:
        if form.is_valid():
            app = form.save(request.user)
            messages.success(request, f"Imported {app.name!r}: {app.task_count} tasks, {app.edge_count} edges.")
            for warning in form.cleaned_data.get("warnings", []):
                messages.warning(request, warning)
            return redirect("dashboard:application", pk=app.pk)
        return _application_list_page(request, fleets, form, GenerateForm(fleets=fleets), status=400)
    return _application_list_page(request, fleets, form, GenerateForm(fleets=fleets))


@login_required
@require_POST
def application_generate(request: HttpRequest) -> HttpResponse:
    fleets = visible_fleets(request)
    form = GenerateForm(request.POST, fleets=fleets)
    if form.is_valid():
        app = form.save(request.user)
        messages.success(request, f"Generated {app.name!r}: {app.task_count} tasks, {app.edge_count} edges.")
        return redirect("dashboard:application", pk=app.pk)
    return _application_list_page(request, fleets, UploadForm(fleets=fleets), form, status=400)


def _application_list_page(request, fleets, upload: UploadForm, generate: GenerateForm, status: int = 200):
    apps = (
        scoped(request, Application.objects.select_related("fleet"))
        .annotate(schedule_count=Count("schedules"))
        .order_by("-created", "-pk")
    )
    return render(
        request,
        "dashboard/application_list.html",
        {
            "page": paginate(request, apps),
            "form": upload,
            "generate": generate,
            "has_fleet": fleets.exists(),
            "nav": "applications",
        },
        status=status,
    )


@login_required
def application_detail(request: HttpRequest, pk: int) -> HttpResponse:
    app = get_object_or_404(scoped(request, Application.objects.select_related("fleet")), pk=pk)
    return _application_page(
        request, app, ScheduleForm(application=app), CompareForm(application=app, prefix="compare")
    )


def _application_page(
    request: HttpRequest, app: Application, form: ScheduleForm, compare: CompareForm, status: int = 200
) -> HttpResponse:
    graph = app.graph
    return render(
        request,
        "dashboard/application_detail.html",
        {
            "app": app,
            "graph": graph,
            "figure": charts.to_html(charts.dag_figure(graph), div_id="dag-chart"),
            "form": form,
            "compare": compare,
            "schedules": app.schedules.filter(comparison=None).select_related("cluster")[:20],
            "remaps": app.remaps.select_related("schedule")[:10],
            "comparisons": app.comparisons.select_related("cluster")[:10],
            "nav": "applications",
        },
        status=status,
    )


@login_required
@require_POST
def application_schedule(request: HttpRequest, pk: int) -> HttpResponse:
    app = get_object_or_404(scoped(request, Application.objects.select_related("fleet")), pk=pk)
    form = ScheduleForm(request.POST, application=app, request=request)
    if not form.is_valid():
        return _application_page(request, app, form, CompareForm(application=app, prefix="compare"), status=400)
    job = start_job(SchedulingJob.SCHEDULE, app.fleet, form.job_arguments(), request.user)
    return redirect("dashboard:job", pk=job.pk)


@login_required
@require_POST
def application_compare(request: HttpRequest, pk: int) -> HttpResponse:
    app = get_object_or_404(scoped(request, Application.objects.select_related("fleet")), pk=pk)
    form = CompareForm(request.POST, application=app, prefix="compare", request=request)
    if not form.is_valid():
        return _application_page(request, app, ScheduleForm(application=app), form, status=400)
    job = start_job(SchedulingJob.COMPARE, app.fleet, form.job_arguments(), request.user)
    return redirect("dashboard:job", pk=job.pk)


# ---- schedules ----------------------------------------------------------------------------------------
@login_required
def schedule_list(request: HttpRequest) -> HttpResponse:
    schedules = scoped(request, Schedule.objects.for_list()).order_by("-created", "-pk")
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
    cpus = {p["id"]: p.get("cores", 1) for p in schedule.platform.get("processors", []) if "id" in p}
    return render(
        request,
        "dashboard/schedule_detail.html",
        {
            "schedule": schedule,
            "metrics": schedule_metrics(schedule.metrics, dag.time_unit),
            "idle_rows": idle_rows(schedule.metrics, schedule.makespan, cpus),
            "multicore": any(n > 1 for n in cpus.values()),
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


def schedule_metrics(metrics: dict, unit: str) -> list[tuple[str, object, str]]:
    """The figures of a schedule worth a headline: (label, value, unit or "%"), only those it has."""
    u = f" {unit}" if unit else ""
    rows: list[tuple[str, object, str]] = []
    frames = metrics.get("frames") or 1
    if frames > 1:
        rows.append(("Frames", frames, ""))
        rows.append(("Mean frame latency", metrics.get("mean_latency"), u))
        if metrics.get("throughput") is not None:
            rows.append(("Throughput", metrics["throughput"], f" frames per{u or ' time unit'}"))
        if metrics.get("throughput_per_s") is not None:
            rows.append(("Throughput", metrics["throughput_per_s"], " frames/s"))
        if metrics.get("pipeline_gain") is not None:
            rows.append(("Pipeline gain", 100 * metrics["pipeline_gain"], " %"))
        rows.append(("Frame buffers used", metrics.get("buffers_used"), ""))
    for key, label, scale, suffix in (
        ("slr", "SLR", 1, ""),
        ("idle", "Idle time", 100, " %"),
        ("overlap", "Overlap O(A)", 1, u),
        ("xo", "Exclusive overlap XO(A)", 1, u),
        ("xo_efficiency", "XO efficiency", 100, " %"),
    ):
        if metrics.get(key) is not None:
            rows.append((label, scale * metrics[key], suffix))
    return rows


def idle_rows(
    metrics: dict, makespan: float, cpus: dict[str, int] | None = None
) -> list[tuple[str, int, float, float | None]]:
    """(processor, CPUs, idle time, idle %) for the idle-per-processor table; a multi-core processor's idle
    time is CPU time (summed over its CPUs), so its % is of ``CPUs * makespan``."""
    idle = metrics.get("idle_per_processor") or {}
    cpus = cpus or {}
    rows = []
    for p, t in idle.items():
        n = cpus.get(p, 1)
        rows.append((p, n, t, 100 * t / (n * makespan) if makespan else None))
    return rows


@login_required
@require_POST
def schedule_push(request: HttpRequest, pk: int) -> HttpResponse:
    schedule = get_object_or_404(scoped(request, Schedule.objects.select_related("fleet", "cluster")), pk=pk)
    if schedule.cluster is None or not schedule.cluster.kubeconfig:
        messages.error(request, "This schedule's cluster has no Kubernetes API configured: nothing to push to.")
        return redirect("dashboard:schedule", pk=schedule.pk)
    if SchedulingJob.PUSH_SCHEDULE not in HANDLERS:
        messages.error(request, "Pushing to Kubernetes is not available in this installation.")
        return redirect("dashboard:schedule", pk=schedule.pk)
    job = start_job(SchedulingJob.PUSH_SCHEDULE, schedule.fleet, {"schedule": schedule.pk}, request.user)
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


# ---- comparisons --------------------------------------------------------------------------------------
@login_required
def comparison_list(request: HttpRequest) -> HttpResponse:
    comparisons = scoped(request, Comparison.objects.select_related("fleet", "application", "cluster")).order_by(
        "-created", "-pk"
    )
    return render(
        request, "dashboard/comparison_list.html", {"page": paginate(request, comparisons), "nav": "comparisons"}
    )


@login_required
def comparison_detail(request: HttpRequest, pk: int) -> HttpResponse:
    comparison = get_object_or_404(
        scoped(request, Comparison.objects.select_related("fleet", "application", "cluster", "job")), pk=pk
    )
    schedules = comparison.ordered_schedules()
    dag = comparison.application.graph
    platform = Platform.from_dict(comparison.platform)
    engine = [(s.algorithm, s.to_engine()) for s in schedules]
    problem = ""
    try:
        fig = charts.comparison_figure(engine, platform=platform, dag=dag)
    except (InputError, KeyError) as exc:
        problem = f"the application changed since this comparison was made ({exc}); critical paths are not shown"
        fig = charts.comparison_figure(engine, platform=platform, time_unit=dag.time_unit)
    results = comparison.result.get("results", {})
    shown = [a for a in comparison.algorithms if a in results]
    rows = [
        {"algorithm": a, "schedule": next((s for s in schedules if s.algorithm == a), None), **results[a]}
        for a in shown
    ]
    frames = comparison.result.get("frames", 1)
    return render(
        request,
        "dashboard/comparison_detail.html",
        {
            "comparison": comparison,
            "title": " vs ".join(a.upper() for a in comparison.algorithms),
            "rows": rows,
            "frames": frames,
            "unit": dag.time_unit,
            "problem": problem,
            "gantt": charts.to_html(fig, div_id="comparison-gantt"),
            "bars": charts.to_html(charts.comparison_bars_figure(results, shown), div_id="comparison-bars"),
            "processor_count": len(platform.processors),
            "relative": [(a, [comparison.result["relative"][a].get(b) for b in shown]) for a in shown],
            "nav": "comparisons",
        },
    )


# ---- devices ------------------------------------------------------------------------------------------
@login_required
def device_list(request: HttpRequest) -> HttpResponse:
    return render(request, "dashboard/device_list.html", {"devices": DeviceProfile.objects.all(), "nav": "devices"})


@login_required
def device_detail(request: HttpRequest, slug: str) -> HttpResponse:
    device = get_object_or_404(DeviceProfile, slug=slug)
    form = AdviceForm(request.POST if request.method == "POST" else None, device=device)
    answer = None
    status = 200
    if request.method == "POST":
        status = 400
        if form.is_valid():
            serializer = AdviceRequestSerializer(data=form.request_data(), context={"device": device})
            if serializer.is_valid():
                try:
                    answer = advice(device, serializer)
                    status = 200
                except InputError as exc:
                    form.add_error(exc.field if exc.field in form.fields else None, str(exc))
            else:
                for field, errors in serializer.errors.items():
                    for error in errors:
                        form.add_error(field if field in form.fields else None, str(error))
    figure = charts.uma_zone_figure(
        device.cpu_threshold_pct,
        device.gpu_threshold_low_pct,
        device.gpu_threshold_high_pct,
        answer["advice"]["cpu_usage"] if answer else None,
        answer["advice"]["gpu_usage"] if answer else None,
    )
    return render(
        request,
        "dashboard/device_detail.html",
        {
            "device": device,
            "form": form,
            "answer": answer,
            "figure": charts.to_html(figure, div_id="zone-chart"),
            "nav": "devices",
        },
        status=status,
    )
