"""Scheduling pages: schedules (Gantt chart, figures, push to Kubernetes), comparisons, and the actions of
the application page that start scheduling and comparison jobs. Login required, fleet-scoped.

Apps above this one extend the schedule page with panels (``apps.ui.panels``, host
``"scheduling.schedule"``, slots ``notice``, ``gantt_intro`` and ``after_gantt``); the page never imports
them. A panel function is called as ``fn(request, schedule, engine=..., platform=..., dag=..., critical=...,
**state)`` with the stored schedule as an engine schedule, its platform, the application's DAG, the critical
path and what :func:`schedule_page` was given; a panel may return ``figure`` (HTML) to replace the page's
Gantt chart and ``gantt_title`` to complete its heading. This app's own panel on the application page
(host ``"workloads.application"``) holds the schedule and compare forms and the schedules made.
"""

from __future__ import annotations

from urllib.parse import urlencode

from django.contrib import messages
from django.contrib.auth.decorators import login_required
from django.core.paginator import Paginator
from django.db.models import Count
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, redirect, render
from django.urls import reverse
from django.views.decorators.http import require_POST

from apps.jobs.registry import HANDLERS
from apps.jobs.services import start_job
from apps.scheduling.forms import CompareForm, ScheduleForm
from apps.scheduling.kinds import SchedulingJob
from apps.ui import charts
from apps.ui.helpers import paginate, scoped, search_q, search_term
from apps.ui.links import register_result_page
from apps.ui.panels import register_panel, render_panels
from apps.workloads.models import Application
from apps.workloads.views import APPLICATION_PAGE, application_page
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform

from . import charts as scheduling_charts
from .api import COMPARISON_SEARCH, SCHEDULE_SEARCH
from .models import Assignment, Comparison, Schedule
from .serializers import AssignmentFilterSerializer

SCHEDULE_PAGE = "scheduling.schedule"


# ---- the application page's scheduling panel -------------------------------------------------------
def application_panel(
    request: HttpRequest,
    app: Application,
    *,
    schedule_form: ScheduleForm | None = None,
    compare_form: CompareForm | None = None,
    **_: object,
) -> dict:
    """The schedule and compare forms (bound ones when a POST was refused) and the schedules made."""
    return {
        "form": schedule_form or ScheduleForm(application=app, request=request),
        "compare": compare_form or CompareForm(application=app, prefix="compare", request=request),
        "schedules": app.schedules.filter(comparison=None).select_related("cluster")[:20],
        "comparisons": app.comparisons.select_related("cluster")[:10],
    }


def register() -> None:
    """Add the scheduling panel to the application page and the schedule and comparison pages as the pages
    of job results naming them (called by the app's ``ready()``)."""
    register_result_page("schedule", "scheduling:schedule", order=20)
    register_result_page("comparison", "scheduling:comparison", order=40)
    register_panel(
        APPLICATION_PAGE,
        "scheduling",
        application_panel,
        templates={
            "side": "scheduling/includes/application_forms.html",
            "main": "scheduling/includes/application_schedules.html",
        },
        order=10,
    )


@login_required
@require_POST
def application_schedule(request: HttpRequest, pk: int) -> HttpResponse:
    app = get_object_or_404(scoped(request, Application.objects.select_related("fleet")), pk=pk)
    form = ScheduleForm(request.POST, application=app, request=request)
    if not form.is_valid():
        return application_page(request, app, status=400, schedule_form=form)
    job = start_job(SchedulingJob.SCHEDULE, app.fleet, form.job_arguments(), request.user)
    return redirect("jobs:job", pk=job.pk)


@login_required
@require_POST
def application_compare(request: HttpRequest, pk: int) -> HttpResponse:
    app = get_object_or_404(scoped(request, Application.objects.select_related("fleet")), pk=pk)
    form = CompareForm(request.POST, application=app, prefix="compare", request=request)
    if not form.is_valid():
        return application_page(request, app, status=400, compare_form=form)
    job = start_job(SchedulingJob.COMPARE, app.fleet, form.job_arguments(), request.user)
    return redirect("jobs:job", pk=job.pk)


# ---- schedules ----------------------------------------------------------------------------------------
@login_required
def schedule_list(request: HttpRequest) -> HttpResponse:
    term = search_term(request)
    schedules = scoped(request, Schedule.objects.for_list()).filter(search_q(term, SCHEDULE_SEARCH))
    schedules = schedules.order_by("-created", "-pk")
    return render(
        request,
        "scheduling/schedule_list.html",
        {"page": paginate(request, schedules), "search": term, "nav": "schedules"},
    )


@login_required
def schedule_detail(request: HttpRequest, pk: int) -> HttpResponse:
    schedule = get_object_or_404(
        scoped(request, Schedule.objects.select_related("fleet", "application", "cluster", "job")), pk=pk
    )
    return schedule_page(request, schedule)


#: Rows of the schedule page's assignment table per page (the whole table of a 1000 x 10 schedule was 10,010
#: rows, 5.5 MB of HTML: issue 13).
TABLE_PAGE_SIZE = 100


def schedule_page(request: HttpRequest, schedule: Schedule, status: int = 200, **state) -> HttpResponse:
    """The schedule page with every registered panel; ``state`` goes to the panels (HEFT4K's bound what-if
    form, for instance). The assignment table is one page of the schedule's rows, filtered by the query
    string (``task``, ``processor``, ``frame``, ``placement``: the API's assignment filter) and paginated in
    the database; the figures come from aggregates, so the page's size does not grow with the rows."""
    engine = schedule.to_engine()
    dag = schedule.application.graph
    gantt = _gantt(request, schedule, engine, dag, state)
    table = _assignment_table(request, schedule, engine, gantt["critical"])
    if table["filter_errors"] and status == 200:
        status = 400
    return render(
        request,
        "scheduling/schedule_detail.html",
        {
            "schedule": schedule,
            **_figures(schedule, dag.time_unit),
            "time_unit": dag.time_unit,
            "push_blocked": push_blocked(schedule),
            **table,
            **gantt,
            "unit": dag.time_unit,
            "nav": "schedules",
        },
        status=status,
    )


def _assignment_table(request: HttpRequest, schedule: Schedule, engine, critical: list[tuple[str, int]]) -> dict:
    """One page of the assignment table (filtered by the query string), the filter's choices and errors, and
    what the page says about all the rows (counted in the database)."""
    processors = [p.get("id") for p in schedule.platform.get("processors", []) if isinstance(p, dict)]
    processors += sorted({a.processor for a in engine.assignments} - set(processors))
    frames = sorted({a.frame for a in engine.assignments})
    query = {k: v for k, v in request.GET.items() if k in AssignmentFilterSerializer._declared_fields and v != ""}
    filters = AssignmentFilterSerializer(data=query, context={"request": request, "processors": set(processors)})
    rows = schedule.assignments.all()
    errors: dict = {}
    if filters.is_valid():
        rows = filters.filter(rows)
    else:
        errors = {k: " ".join(str(m) for m in v) for k, v in filters.errors.items()}
        rows = rows.none()
    page = Paginator(rows, TABLE_PAGE_SIZE).get_page(request.GET.get("page"))
    on_path = set(critical)
    for row in page:
        row.on_critical_path = (row.task, row.frame) in on_path
        row.duration = row.finish - row.start
    counts = dict(schedule.assignments.order_by().values_list("placement").annotate(n=Count("pk")))
    busy: dict[str, list[float]] = {}
    for a in engine.assignments:
        entry = busy.setdefault(a.processor, [0, 0.0])
        entry[0] += 1
        entry[1] += a.finish - a.start
    return {
        "page": page,
        "task_count": len(engine.assignments),
        "filter": query,
        "filter_query": urlencode(query),
        "filter_errors": errors,
        "processors": processors,
        "frames": frames,
        "per_processor": [(p, *busy.get(p, (0, 0.0))) for p in processors],
        "critical_tasks": [t if len(frames) <= 1 else f"{t} [{f}]" for t, f in critical],
        "placement": [(value, label, counts.get(value, 0)) for value, label in Assignment.Placement.choices],
        "can_push": bool(schedule.cluster and schedule.cluster.kubeconfig),
        "processor_count": len(schedule.platform.get("processors", [])),
        "has_niceness": any(a.niceness is not None for a in engine.assignments),
    }


def _gantt(request: HttpRequest, schedule: Schedule, engine, dag, state: dict) -> dict:
    """The Gantt chart (a panel's when one draws it), the critical path, the panels and any problem."""
    critical: list[tuple[str, int]] = []
    panels = []
    gantt_title = ""
    problem = ""
    try:
        platform = schedule.engine_platform()
        critical = engine.critical_path(dag, platform)
        panels = render_panels(
            SCHEDULE_PAGE, request, schedule, engine=engine, platform=platform, dag=dag, critical=critical, **state
        )
        figure = None
        for panel in panels:
            if "figure" in panel.context:
                figure = panel.context.pop("figure")
                gantt_title = panel.context.get("gantt_title", "")
        if figure is None:
            fig = charts.gantt_figure(engine, platform=platform, dag=dag, critical=critical)
            scheduling_charts.keep_idle_rows(fig, [charts.GanttPanel("", engine, platform)], lanes=False, stacked=False)
            figure = charts.to_html(fig, div_id="gantt-chart")
    except (InputError, KeyError) as exc:
        # The application's DAG changed since this schedule was made; draw what was stored.
        problem = f"the application changed since this schedule was made ({exc}); the critical path is not shown"
        panels, gantt_title = [], ""
        nice = any(a.niceness is not None for a in engine.assignments)
        fig = charts.gantt_figure(engine, time_unit=dag.time_unit, colour_by_niceness=nice)
        figure = charts.to_html(fig, div_id="gantt-chart")
    return {"figure": figure, "critical": critical, "panels": panels, "gantt_title": gantt_title, "problem": problem}


def _figures(schedule: Schedule, unit: str) -> dict:
    """The schedule's headline figures and idle time per processor."""
    cpus = {p["id"]: p.get("cores", 1) for p in schedule.platform.get("processors", []) if "id" in p}
    return {
        "metrics": schedule_metrics(schedule.metrics, unit),
        "idle_rows": idle_rows(schedule.metrics, schedule.makespan, cpus),
        "multicore": any(n > 1 for n in cpus.values()),
    }


def _xeft_note(shown: list[str], results: dict, dag, platform: Platform) -> str:
    """Why XEFT equals HEFT on this comparison, when it does: XEFT only reorders *exclusive* tasks, balancing
    CPU-only against GPU-only ones (thesis Algorithm 1), so without both kinds (or without a GPU) it is HEFT."""
    if not {"heft", "xeft"} <= set(shown):
        return ""
    if results["xeft"].get("makespan") != results["heft"].get("makespan"):
        return ""
    has_gpu = any(p.cls == "gpu" for p in platform.processors)
    gpu_only = any(set(t.cost) == {"gpu"} for t in dag.tasks.values())
    cpu_only = any(set(t.cost) == {"cpu"} for t in dag.tasks.values())
    if not has_gpu:
        why = "the target has no GPU"
    elif not gpu_only:
        why = "the DAG has no GPU-only task (every task runs on a CPU)"
    elif not cpu_only:
        why = "the DAG has no CPU-only task"
    else:
        why = "no cluster of exclusive tasks improved the balance here"
    return (
        f"XEFT equals HEFT here: {why}. XEFT is HEFT with CPU-only and GPU-only tasks grouped to overlap "
        "(thesis 3.1.1, Algorithm 1); it differs only when both kinds of exclusive task and a GPU are present."
    )


def _heft4k_note(shown: list[str], results: dict, best: str) -> str:
    """Why HEFT4K is marked best against HEFT, when it is: it places each task with a look-ahead over its
    children on every CPU (Bittencourt's HEFT, the thesis's ref. [94]) where HEFT takes the earliest finish,
    and its makespan is the synchronised plan, which Kubernetes does not impose (only the mapping and the
    niceness reach the cluster)."""
    if best != "heft4k" or "heft" not in shown:
        return ""
    ours, heft = results["heft4k"].get("makespan"), results["heft"].get("makespan")
    if not ours or not heft:
        return ""
    gain = (heft - ours) / heft
    return (
        f"HEFT4K is best here, {gain:.1%} below HEFT: it keeps HEFT's ranks but places each task with a "
        "look-ahead over its children's finish times on every CPU (thesis 3.3.2; look-ahead HEFT, ref. [94]), "
        "where HEFT takes the task's own earliest finish. Its makespan is the ideal synchronised plan: on "
        "Kubernetes only the task-to-node mapping and the niceness are applied, so a run can take longer "
        "(the HEFT4K page simulates it)."
        if gain > 0
        else "HEFT4K is marked best with the same makespan as HEFT: ties go to the algorithm listed first."
    )


def push_blocked(schedule: Schedule) -> tuple[str, str, str] | None:
    """Why this schedule cannot be pushed to Kubernetes (reason, link, link text), or ``None`` when it can."""
    if schedule.cluster is None:
        return (
            "scheduled on a model platform, not a cluster",
            reverse("workloads:application", args=[schedule.application_id]) + "#schedule",
            "schedule it on a cluster",
        )
    if not schedule.cluster.kubeconfig:
        return (
            f"cluster {schedule.cluster.name} has no Kubernetes API configured",
            reverse("clusters:cluster", args=[schedule.cluster_id]) + "#kubernetes",
            "connect it",
        )
    return None


def schedule_metrics(metrics: dict, unit: str) -> list[tuple[str, object, str]]:
    """The figures of a schedule worth a headline: (label, value, unit or "%"), only those it has."""
    u = f" {unit}" if unit else ""
    rows: list[tuple[str, object, str]] = []
    frames = metrics.get("frames") or 1
    if frames > 1:
        rows.append(("Frames", frames, ""))
        rows.append(("Mean frame latency", metrics.get("mean_latency"), u))
        # One throughput, in frames/s when the time unit converts (not "frames per ms" next to "frames/s").
        rate, per_s = scheduling_charts.rate_unit(unit)
        if metrics.get("throughput_per_s") is not None and rate == "frames/s":
            rows.append(("Throughput", metrics["throughput_per_s"], " frames/s"))
        elif metrics.get("throughput") is not None:
            rows.append(("Throughput", metrics["throughput"] * per_s, f" {rate}"))
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
    blocked = push_blocked(schedule)
    if blocked is not None:
        messages.error(request, f"Nothing to push to: {blocked[0]}.")
        return redirect("scheduling:schedule", pk=schedule.pk)
    if SchedulingJob.PUSH_SCHEDULE not in HANDLERS:
        messages.error(request, "Pushing to Kubernetes is not available in this installation.")
        return redirect("scheduling:schedule", pk=schedule.pk)
    job = start_job(SchedulingJob.PUSH_SCHEDULE, schedule.fleet, {"schedule": schedule.pk}, request.user)
    return redirect("jobs:job", pk=job.pk)


# ---- comparisons ----------------------------------------------------------------------------------
@login_required
def comparison_list(request: HttpRequest) -> HttpResponse:
    term = search_term(request)
    comparisons = scoped(request, Comparison.objects.for_list()).filter(search_q(term, COMPARISON_SEARCH))
    comparisons = comparisons.order_by("-created", "-pk")
    return render(
        request,
        "scheduling/comparison_list.html",
        {"page": paginate(request, comparisons), "search": term, "nav": "comparisons"},
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
        fig = scheduling_charts.comparison_figure(engine, platform=platform, dag=dag)
    except (InputError, KeyError) as exc:
        problem = f"the application changed since this comparison was made ({exc}); critical paths are not shown"
        fig = scheduling_charts.comparison_figure(engine, platform=platform, time_unit=dag.time_unit)
    results = comparison.result.get("results", {})
    shown = [a for a in comparison.algorithms if a in results]
    rows = [
        {"algorithm": a, "schedule": next((s for s in schedules if s.algorithm == a), None), **results[a]}
        for a in shown
    ]
    frames = comparison.result.get("frames", 1)
    normalise = request.GET.get("normalise") == "1"
    rate, per_s = scheduling_charts.rate_unit(dag.time_unit)
    for row in rows:  # one spelling of throughput on every page: frames/s
        row["throughput_shown"] = None if row.get("throughput") is None else row["throughput"] * per_s
    return render(
        request,
        "scheduling/comparison_detail.html",
        {
            "comparison": comparison,
            "title": " vs ".join(a.upper() for a in comparison.algorithms),
            "rows": rows,
            "frames": frames,
            "unit": dag.time_unit,
            "problem": problem,
            "gantt": charts.to_html(fig, div_id="comparison-gantt"),
            "bars": charts.to_html(
                scheduling_charts.comparison_bars_figure(results, shown, dag.time_unit, normalise),
                div_id="comparison-bars",
            ),
            "normalise": normalise,
            "reference": scheduling_charts.normalisation_reference(results, shown) if shown else "",
            "rate_unit": rate,
            "xeft_note": _xeft_note(shown, results, dag, platform),
            "heft4k_note": _heft4k_note(shown, results, comparison.best),
            "processor_count": len(platform.processors),
            "relative": [(a, [comparison.result["relative"][a].get(b) for b in shown]) for a in shown],
            "nav": "comparisons",
        },
    )
