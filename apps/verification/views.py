"""Dashboard pages of assertion-based verification: assertions with their status and violations, the
monitor-to-node map, allocation runs and the Fig. 4.24-style migration timeline of a simulation. Every
page needs a login and shows only the user's fleets' objects (another fleet's answers 404)."""

from __future__ import annotations

from django.contrib.auth.decorators import login_required
from django.db.models import Count, Max, Min
from django.http import Http404, HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, redirect, render
from django.views.decorators.http import require_POST

from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.tenancy.scoping import visible_fleets
from apps.ui.charts import to_html
from apps.ui.helpers import paginate, scoped
from apps.verification.kinds import VerificationJob

from . import charts
from .forms import SimulationForm
from .models import AllocationRun, Assertion, Handler, MigrationEvent, Monitor, Violation

NAV = "verification"


@login_required
def overview(request: HttpRequest) -> HttpResponse:
    fleets = visible_fleets(request)
    assertions = list(
        scoped(request, Assertion.objects.select_related("fleet").prefetch_related("monitors"))
        .annotate(violations=Count("monitors__violations"), last_violation=Max("monitors__violations__created"))
        .order_by("name")
    )
    monitors = scoped(request, Monitor.objects.select_related("cluster", "node", "assertion"))
    maps = []
    for cluster_id in monitors.values_list("cluster", flat=True).distinct().order_by("cluster"):
        rows = [m for m in monitors if m.cluster_id == cluster_id]
        cluster = rows[0].cluster
        handlers = {h.node_id: h for h in Handler.objects.filter(cluster=cluster)}
        columns = []
        for node in cluster.nodes.order_by("name"):
            columns.append(
                {"node": node, "handler": handlers.get(node.pk), "monitors": [m for m in rows if m.node_id == node.pk]}
            )
        unplaced = [m for m in rows if m.node_id is None]
        maps.append({"cluster": cluster, "columns": columns, "unplaced": unplaced, "total": len(rows)})
    recent = scoped(request, Violation.objects.select_related("monitor", "monitor__assertion"), "monitor__fleet")[:15]
    runs = scoped(request, AllocationRun.objects.filter(series__isnull=True).select_related("cluster"))[:10]
    series = (
        scoped(request, AllocationRun.objects.filter(series__isnull=False))
        .values("series", "scenario")
        .annotate(start=Min("created"), periods=Count("id"))
        .order_by("-start")[:10]
    )
    return render(
        request,
        "verification/overview.html",
        {
            "assertions": assertions,
            "maps": maps,
            "recent": recent,
            "runs": runs,
            "series": series,
            "form": SimulationForm(fleets=fleets),
            "has_fleet": fleets.exists(),
            "nav": NAV,
        },
    )


@login_required
@require_POST
def simulate(request: HttpRequest) -> HttpResponse:
    form = SimulationForm(request.POST, fleets=visible_fleets(request))
    if not form.is_valid():
        raise Http404("no such fleet")
    job = start_job(
        VerificationJob.VERIFICATION_SIMULATION,
        form.cleaned_data["fleet"],
        form.job_arguments(),
        request.user,
    )
    if job.state == Job.State.SUCCEEDED and (job.result or {}).get("page"):
        return redirect(job.result["page"])
    return redirect("jobs:job", pk=job.pk)


@login_required
def assertion_detail(request: HttpRequest, pk: int) -> HttpResponse:
    assertion = get_object_or_404(scoped(request, Assertion.objects.select_related("fleet")), pk=pk)
    monitors = assertion.monitors.select_related("cluster", "node").order_by("cluster__name", "name")
    violations = Violation.objects.filter(monitor__assertion=assertion).select_related("monitor")
    return render(
        request,
        "verification/assertion_detail.html",
        {"assertion": assertion, "monitors": monitors, "page": paginate(request, violations), "nav": NAV},
    )


@login_required
def series_detail(request: HttpRequest, series) -> HttpResponse:
    runs = list(scoped(request, AllocationRun.objects.filter(series=series)).order_by("t", "pk"))
    if not runs:
        raise Http404("no such simulation")
    migrations = list(MigrationEvent.objects.filter(run__series=series).order_by("t", "monitor_name"))
    last = runs[-1].result or {}
    summary = last.get("summary", {})
    figure = to_html(charts.timeline_figure(runs, migrations, summary.get("requirement_ms")), div_id="timeline-chart")
    steps: dict[tuple, dict] = {}
    for m in migrations:
        row = steps.setdefault(
            (m.t, m.source, m.target), {"t": m.t, "source": m.source, "target": m.target, "count": 0, "events": 0}
        )
        row["count"] += 1
        row["events"] += m.events_moved or 0
    placement = last.get("placement", {})
    nodes = list(runs[0].nodes)
    final_map = [{"node": n, "monitors": sorted(i for i, j in placement.items() if j == n)} for n in nodes]
    solved = [r.solve_time_ms for r in runs if r.result and not r.result.get("reused") and r.solve_time_ms is not None]
    return render(
        request,
        "verification/series_detail.html",
        {
            "runs": runs,
            "first": runs[0],
            "summary": summary,
            "violations": last.get("violations", []),
            "legs": last.get("legs", []),
            "figure": figure,
            "steps": sorted(steps.values(), key=lambda r: (r["t"], r["source"], r["target"])),
            "final_map": final_map,
            "milp_mean": sum(solved) / len(solved) if solved else None,
            "nav": NAV,
        },
    )


@login_required
def run_detail(request: HttpRequest, pk: int) -> HttpResponse:
    run = get_object_or_404(scoped(request, AllocationRun.objects.select_related("cluster", "job")), pk=pk)
    if run.series is not None:
        return redirect("verification:series", series=run.series)
    result = run.result or {}
    nodes = [
        {"name": n, **info, "overloaded": result.get("overloaded", {}).get(n)} for n, info in sorted(run.nodes.items())
    ]
    return render(
        request,
        "verification/run_detail.html",
        {"run": run, "result": result, "nodes": nodes, "migrations": run.migrations.all()[:500], "nav": NAV},
    )
