"""HEFT4K pages of the dashboard: the schedule panel (niceness, predicted vs simulated Gantt, "fail this
node" what-if), remap events and their history. Every page needs a login and is scoped to the user's fleets."""

from __future__ import annotations

from django import forms
from django.conf import settings
from django.contrib import messages
from django.contrib.auth.decorators import login_required
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, redirect, render
from django.views.decorators.http import require_POST

from apps.dashboard import charts
from apps.heft4k.kinds import Heft4kJob
from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.scheduling.models import Schedule
from apps.tenancy.scoping import visible_fleets
from apps.workloads.models import Application
from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Schedule as EngineSchedule
from continuum.engine.heft4k.k8s_baselines import Unschedulable, run_heft4k, run_heft_k8s, run_k8s_default

from . import remapping
from .models import RemapEvent

#: Above this many tasks the schedule page does not run the simulator on every view.
SIMULATE_MAX_TASKS = 3000


class WhatIfForm(forms.Form):
    """Fail one node of a schedule and see Algorithm 2's remap before anything is pushed."""

    node = forms.ChoiceField(label="Fail node")
    threshold = forms.FloatField(
        required=False,
        min_value=0,
        max_value=100,
        label="Threshold (%)",
        help_text="total remap when the lost share of the HEFT ranks exceeds this",
    )

    def __init__(self, *args, schedule: Schedule, **kwargs):
        super().__init__(*args, **kwargs)
        self.schedule = schedule
        counts: dict[str, int] = {}
        for processor in schedule.assignments.values_list("processor", flat=True):
            counts[processor] = counts.get(processor, 0) + 1
        self.fields["node"].choices = [
            (n, f"{n} ({counts.get(n, 0)} task{'s' if counts.get(n, 0) != 1 else ''})")
            for n in remapping.schedule_nodes(schedule)
        ]
        self.fields["threshold"].initial = round(100 * settings.CONTINUUM_REMAP_THRESHOLD, 6)
        self.fields["threshold"].widget.attrs["step"] = "any"

    def clean(self):
        data = super().clean()
        if "node" not in data:
            return data
        threshold = data.get("threshold")
        data["fraction"] = None if threshold is None else threshold / 100.0
        try:
            remapping.check(self.schedule, [data["node"]], data["fraction"])
        except InputError as exc:
            self.add_error("threshold" if exc.field == "threshold" else "node", str(exc))
        return data

    def job_arguments(self) -> dict:
        return {
            "schedule": self.schedule.pk,
            "fail": [self.cleaned_data["node"]],
            "what_if": True,
            "threshold": self.cleaned_data["fraction"],
            "trigger": RemapEvent.Trigger.WHAT_IF,
        }


def _scoped(request: HttpRequest, qs, lookup: str = "fleet"):
    return qs.filter(**{f"{lookup}__in": visible_fleets(request)})


# ---- the schedule page's HEFT4K panel --------------------------------------------------------------
def schedule_panel(
    schedule: Schedule,
    engine: EngineSchedule,
    platform: Platform,
    dag: TaskGraph,
    critical: list[tuple[str, int]],
    whatif_form: WhatIfForm | None = None,
) -> dict | None:
    """What the schedule page shows for a HEFT4K schedule (one whose tasks carry a niceness), else None:
    the predicted plan and its CFS-simulated run on one time axis, the simulated makespans of the
    baselines, the what-if form and the remaps of this schedule."""
    if not any(a.niceness is not None for a in engine.assignments):
        return None
    panel: dict = {
        "form": whatif_form or WhatIfForm(schedule=schedule),
        "can_remap": len(remapping.schedule_nodes(schedule)) > 1 and all(a.frame == 0 for a in engine.assignments),
        "origin": RemapEvent.objects.filter(new_schedule=schedule).first(),
        "remaps": list(schedule.remaps.all()[:10]),
        "simulated": [],
        "simulation_note": "",
    }
    predicted = charts.GanttPanel("Predicted (HEFT4K plan, synchronised)", engine, platform, set(critical))
    panels = [predicted]
    frames = len({a.frame for a in engine.assignments})
    if len(dag.tasks) > SIMULATE_MAX_TASKS:
        panel["simulation_note"] = f"not simulated: more than {SIMULATE_MAX_TASKS} tasks"
    elif frames > 1:
        # The CFS simulator runs one instance of the DAG; it would fold the frames onto one mapping.
        panel["simulation_note"] = f"not simulated: the CFS simulation runs one frame and this schedule has {frames}"
    else:
        simulated = run_heft4k(dag, platform, engine)
        notes = _sharing_notes(simulated, dag, platform, dag.time_unit)
        panels.append(
            charts.GanttPanel("Simulated on Kubernetes (Linux CFS, niceness)", simulated, platform, set(critical),
                              notes=notes)
        )  # fmt: skip
        panel["simulated"] = _baselines(dag, platform, engine, simulated)
    fig = charts.stacked_gantt_figure(panels, dag.time_unit, colour_by_niceness=True)
    panel["figure"] = charts.to_html(fig, div_id="gantt-chart")
    return panel


def _sharing_notes(simulated: EngineSchedule, dag: TaskGraph, platform: Platform, unit: str) -> dict:
    """Hover line for a simulated task: how much longer than its cost it took (CPU shared, preempted)."""
    notes = {}
    for a in simulated.assignments:
        cost = platform.cost(dag.tasks[a.task], platform.processors[platform.index[a.processor]]) or 0.0
        lost = (a.finish - a.start) - cost
        notes[(a.task, a.frame)] = (
            f"cost {cost:.6g} {unit}; {lost:.6g} {unit} lost to CPU sharing" if lost > 1e-9 else "ran alone"
        )
    return notes


def _baselines(dag, platform, plan, simulated) -> list[dict]:
    """Simulated makespans of HEFT4K and the schedulers it is compared with (thesis 4.3.2), same inputs."""
    rows = [
        {"name": "HEFT4K (this mapping, with niceness)", "makespan": simulated.makespan},
        {
            "name": "HEFT on Kubernetes (this mapping, all nice 0)",
            "makespan": run_heft_k8s(dag, platform, plan).makespan,
        },
    ]
    try:
        default = run_k8s_default(dag, platform).makespan
    except Unschedulable:
        default = None
    rows.append({"name": "default Kubernetes scheduler (model)", "makespan": default})
    for row in rows:
        m = row["makespan"]
        row["vs_plan"] = None if m is None or plan.makespan <= 0 else m / plan.makespan - 1.0
    return rows


# ---- what-if and remap pages ------------------------------------------------------------------------
@login_required
@require_POST
def whatif(request: HttpRequest, pk: int) -> HttpResponse:
    schedule = get_object_or_404(
        _scoped(request, Schedule.objects.select_related("fleet", "application", "cluster", "job")), pk=pk
    )
    form = WhatIfForm(request.POST, schedule=schedule)
    if not form.is_valid():
        from apps.dashboard.views import schedule_page

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
    return redirect("dashboard:job", pk=job.pk)


@login_required
def remap_detail(request: HttpRequest, pk: int) -> HttpResponse:
    event = get_object_or_404(
        _scoped(request, RemapEvent.objects.select_related("fleet", "application", "schedule", "new_schedule", "job")),
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
    event = get_object_or_404(_scoped(request, RemapEvent.objects.select_related("fleet", "schedule")), pk=pk)
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
    return redirect("dashboard:job", pk=job.pk)


@login_required
def remap_list(request: HttpRequest) -> HttpResponse:
    from apps.dashboard.views import paginate

    events = _scoped(request, RemapEvent.objects.select_related("application", "schedule"))
    application = None
    if request.GET.get("application", "").isdigit():
        application = get_object_or_404(_scoped(request, Application.objects), pk=int(request.GET["application"]))
        events = events.filter(application=application)
    return render(
        request,
        "heft4k/remap_list.html",
        {"page": paginate(request, events), "application": application, "nav": "remaps"},
    )
