"""HEFT4K pages of the dashboard: the panels it adds to the schedule page (niceness, predicted vs simulated
Gantt, "fail this node" what-if) and the application page (remapping history), remap events and their
history. Every page needs a login and is scoped to the user's fleets.

The host pages never import this module: :func:`register` adds the panels (``apps.ui.panels``) when the
app is ready.
"""

from __future__ import annotations

from django.contrib import messages
from django.contrib.auth.decorators import login_required
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, redirect, render
from django.views.decorators.http import require_POST

from apps.heft4k.kinds import Heft4kJob
from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.scheduling.models import Schedule
from apps.scheduling.views import schedule_page
from apps.ui import charts
from apps.ui.helpers import paginate, scoped
from apps.ui.links import register_result_page
from apps.ui.panels import register_panel
from apps.workloads.models import Application
from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Schedule as EngineSchedule

from . import remapping, simulation
from .forms import WhatIfForm
from .models import RemapEvent, ScheduleSimulation

#: Said on the page of a HEFT4K schedule stored before its job simulated it.
NOT_COMPUTED = "simulation not computed: this schedule was stored before jobs simulated their schedules"


# ---- the schedule page's HEFT4K panel --------------------------------------------------------------
def schedule_panel(
    request: HttpRequest,
    schedule: Schedule,
    *,
    engine: EngineSchedule,
    platform: Platform,
    dag: TaskGraph,
    critical: list[tuple[str, int]],
    whatif_form: WhatIfForm | None = None,
    **_: object,
) -> dict | None:
    """What the schedule page shows for a HEFT4K schedule (one whose tasks carry a niceness), else None:
    the predicted plan and its stored CFS-simulated run on one time axis (its ``figure`` replaces the page's
    Gantt chart), the simulated makespans of the baselines, the what-if form and the remaps of this
    schedule. Nothing is simulated here: the job that stored the schedule did (:mod:`.simulation`)."""
    if not simulation.is_heft4k(engine):
        return None
    stored = ScheduleSimulation.objects.filter(schedule=schedule).first()
    panel: dict = {
        "form": whatif_form or WhatIfForm(schedule=schedule),
        "can_remap": len(remapping.schedule_nodes(schedule)) > 1 and all(a.frame == 0 for a in engine.assignments),
        "origin": RemapEvent.objects.filter(new_schedule=schedule).first(),
        "remaps": list(schedule.remaps.all()[:10]),
        "simulated": [],
        "simulation_note": "",
        "not_computed": stored is None,
    }
    predicted = charts.GanttPanel("Predicted (HEFT4K plan, synchronised)", engine, platform, set(critical))
    panels = [predicted]
    if stored is None:
        panel["simulation_note"] = NOT_COMPUTED
    elif stored.note:
        panel["simulation_note"] = stored.note
    else:
        simulated = EngineSchedule.from_dict(stored.simulated)
        notes = {(task, frame): text for task, frame, text in stored.sharing}
        panels.append(
            charts.GanttPanel("Simulated on Kubernetes (Linux CFS, niceness)", simulated, platform, set(critical),
                              notes=notes)
        )  # fmt: skip
        panel["simulated"] = stored.baselines
    fig = charts.stacked_gantt_figure(panels, dag.time_unit, colour_by_niceness=True)
    panel["figure"] = charts.to_html(fig, div_id="gantt-chart")
    panel["gantt_title"] = ": predicted plan" + (" and simulated run" if panel["simulated"] else "")
    return panel


def application_panel(request: HttpRequest, application: Application, **_: object) -> dict:
    """The application page's remapping history."""
    return {"remaps": application.remaps.select_related("schedule")[:10]}


def register() -> None:
    """Add HEFT4K's panels to the schedule and application pages and its remap page as the page of a job
    result naming a remap (called by the app's ``ready()``)."""
    register_result_page("remap", "heft4k:remap", order=10)
    register_panel(
        "scheduling.schedule",
        "heft4k",
        schedule_panel,
        templates={
            "notice": "heft4k/schedule_origin.html",
            "gantt_intro": "heft4k/schedule_gantt_intro.html",
            "after_gantt": "heft4k/schedule_panel.html",
        },
    )
    register_panel(
        "workloads.application", "heft4k", application_panel, templates={"main": "heft4k/application_remaps.html"}
    )


@login_required
@require_POST
def simulate(request: HttpRequest, pk: int) -> HttpResponse:
    """Start the job that simulates a HEFT4K schedule stored before its job did (never in the request)."""
    schedule = get_object_or_404(scoped(request, Schedule.objects.select_related("fleet")), pk=pk)
    job = start_job(Heft4kJob.SIMULATE, schedule.fleet, {"schedule": schedule.pk}, request.user)
    if job.state == Job.State.SUCCEEDED:
        return redirect("scheduling:schedule", pk=schedule.pk)
    return redirect("jobs:job", pk=job.pk)


# ---- what-if and remap pages ------------------------------------------------------------------------
@login_required
@require_POST
def whatif(request: HttpRequest, pk: int) -> HttpResponse:
    schedule = get_object_or_404(
        scoped(request, Schedule.objects.select_related("fleet", "application", "cluster", "job")), pk=pk
    )
    form = WhatIfForm(request.POST, schedule=schedule)
    if not form.is_valid():
        return schedule_page(request, schedule, whatif_form=form, status=400)
    job = start_job(Heft4kJob.REMAP, schedule.fleet, form.job_arguments(), request.user)
    return _after_job(job)


def _after_job(job: Job) -> HttpResponse:
    """The remap page when the job is done already (no broker), else the job's live progress page."""
    if job.state == Job.State.SUCCEEDED and isinstance((job.result or {}).get("remap"), int):
        return redirect("heft4k:remap", pk=job.result["remap"])
    event = RemapEvent.objects.filter(job=job).first()
    if job.done and event is not None:
        return redirect("heft4k:remap", pk=event.pk)
    return redirect("jobs:job", pk=job.pk)


@login_required
def remap_detail(request: HttpRequest, pk: int) -> HttpResponse:
    event = get_object_or_404(
        scoped(request, RemapEvent.objects.select_related("fleet", "application", "schedule", "new_schedule", "job")),
        pk=pk,
    )
    figure = problem = ""
    try:
        figure = _before_after(event)
    except (InputError, KeyError) as exc:
        problem = f"the schedules cannot be drawn ({exc})"
    old_rows = {a.task: a for a in event.schedule.assignments.all()}
    new_rows = {a.task: a for a in event.new_schedule.assignments.all()} if event.new_schedule else {}
    changes = [
        {
            "task": task,
            "before": old_rows.get(task),
            "after": new_rows.get(task),
            "lost": task in event.lost_tasks,
            "moved": task in event.moved_tasks,
            "pod": next((p for p in event.pods if p.get("task") == task), None),
        }
        for task in event.changed_tasks
    ]
    return render(
        request,
        "heft4k/remap_detail.html",
        {
            "event": event,
            "figure": figure,
            "problem": problem,
            "changes": changes,
            "kept": len(new_rows) - len(changes),
            "cannot_apply": remapping.cannot_apply(event),
            "has_kube": bool(event.schedule.cluster and event.schedule.cluster.kubeconfig),
            "nav": "remaps",
        },
    )


def _before_after(event: RemapEvent) -> str:
    """The schedule before (lost tasks marked) and after the remap (moved tasks marked), one time axis."""
    dag = event.application.graph
    panels = [
        charts.GanttPanel(
            f"Before: schedule #{event.schedule_id}",
            event.schedule.to_engine(),
            event.schedule.engine_platform(),
            {(t, 0) for t in event.lost_tasks},
            f"lost (on {', '.join(event.failed_nodes)})",
            charts.LOST_COLOUR,
        )
    ]
    if event.new_schedule is not None:
        panels.append(
            charts.GanttPanel(
                f"After: {event.decision} remap, schedule #{event.new_schedule_id}",
                event.new_schedule.to_engine(),
                event.new_schedule.engine_platform(),
                {(t, 0) for t in event.changed_tasks},
                "recreated pod",
                charts.MOVED_COLOUR,
            )
        )
    fig = charts.stacked_gantt_figure(panels, dag.time_unit, colour_by_niceness=True)
    return charts.to_html(fig, div_id="remap-chart")


@login_required
@require_POST
def remap_apply(request: HttpRequest, pk: int) -> HttpResponse:
    event = get_object_or_404(scoped(request, RemapEvent.objects.select_related("fleet", "schedule")), pk=pk)
    reason = remapping.cannot_apply(event)
    if reason:
        messages.error(request, f"Cannot apply: {reason}.")
        return redirect("heft4k:remap", pk=event.pk)
    job = start_job(Heft4kJob.REMAP_APPLY, event.fleet, {"remap": event.pk}, request.user)
    if job.state == Job.State.FAILED:
        messages.error(request, f"Applying failed: {job.error}")
        return redirect("heft4k:remap", pk=event.pk)
    if job.state == Job.State.SUCCEEDED:
        event.refresh_from_db()
        messages.success(request, f"Applied: {event.message}.")
        return redirect("heft4k:remap", pk=event.pk)
    return redirect("jobs:job", pk=job.pk)


@login_required
def remap_list(request: HttpRequest) -> HttpResponse:
    events = scoped(request, RemapEvent.objects.select_related("application", "schedule"))
    application = None
    if request.GET.get("application", "").isdigit():
        application = get_object_or_404(scoped(request, Application.objects), pk=int(request.GET["application"]))
        events = events.filter(application=application)
    return render(
        request,
        "heft4k/remap_list.html",
        {"page": paginate(request, events), "application": application, "nav": "remaps"},
    )
