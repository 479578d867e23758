"""HEFT4K's simulated run of a schedule, computed by jobs and stored (:class:`~.models.ScheduleSimulation`):
the schedule page reads it and never simulates in a request.

The CFS simulator runs the plan's mapping with its niceness (what Kubernetes would do: every pod starts at
once, a task runs when its inputs arrive and shares its node's CPUs by nice weight), and the baselines of
thesis 4.3.2 run on the same inputs: the same mapping with every niceness 0, and the default Kubernetes
scheduler's model.
"""

from __future__ import annotations

from django.db import transaction

from apps.scheduling.models import Schedule
from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Schedule as EngineSchedule
from continuum.engine.heft4k.k8s_baselines import Unschedulable, run_heft4k, run_heft_k8s, run_k8s_default

from .models import ScheduleSimulation

#: Above this many tasks a schedule is not simulated (the figure would be unreadable and the job long).
SIMULATE_MAX_TASKS = 3000


def is_heft4k(plan: EngineSchedule) -> bool:
    """A HEFT4K schedule is one whose tasks carry a niceness."""
    return any(a.niceness is not None for a in plan.assignments)


def simulate(plan: EngineSchedule, dag: TaskGraph, platform: Platform) -> dict:
    """The fields of a :class:`ScheduleSimulation` of ``plan``: a note when it is not simulated, else the
    simulated run, the time each task lost to CPU sharing and the baselines' simulated makespans."""
    frames = len({a.frame for a in plan.assignments})
    if len(dag.tasks) > SIMULATE_MAX_TASKS:
        return {"note": f"not simulated: more than {SIMULATE_MAX_TASKS} tasks"}
    if frames > 1:
        # The CFS simulator runs one instance of the DAG; it would fold the frames onto one mapping.
        return {"note": f"not simulated: the CFS simulation runs one frame and this schedule has {frames}"}
    simulated = run_heft4k(dag, platform, plan)
    return {
        "simulated": simulated.to_dict(),
        "sharing": sharing_notes(simulated, dag, platform, dag.time_unit),
        "baselines": baselines(dag, platform, plan, simulated),
    }


def sharing_notes(simulated: EngineSchedule, dag: TaskGraph, platform: Platform, unit: str) -> list[list]:
    """Hover line of each simulated task, ``[task, frame, text]``: how much longer than its cost it took (CPU
    shared, preempted)."""
    notes = []
    for a in simulated.assignments:
        cost = platform.cost(dag.tasks[a.task], platform.processors[platform.index[a.processor]]) or 0.0
        lost = (a.finish - a.start) - cost
        text = f"cost {cost:.6g} {unit}; {lost:.6g} {unit} lost to CPU sharing" if lost > 1e-9 else "ran alone"
        notes.append([a.task, a.frame, text])
    return notes


def baselines(dag: TaskGraph, platform: Platform, plan: EngineSchedule, simulated: EngineSchedule) -> list[dict]:
    """Simulated makespans of HEFT4K and the schedulers it is compared with (thesis 4.3.2), same inputs."""
    rows: list[dict] = [
        {"name": "HEFT4K (this mapping, with niceness)", "makespan": simulated.makespan},
        {
            "name": "HEFT on Kubernetes (this mapping, all nice 0)",
            "makespan": run_heft_k8s(dag, platform, plan).makespan,
        },
    ]
    try:
        default: float | None = run_k8s_default(dag, platform).makespan
    except Unschedulable:
        default = None
    rows.append({"name": "default Kubernetes scheduler (model)", "makespan": default})
    for row in rows:
        m = row["makespan"]
        row["vs_plan"] = None if m is None or plan.makespan <= 0 else m / plan.makespan - 1.0
    return rows


def store(schedule: Schedule) -> ScheduleSimulation | None:
    """Simulate a stored HEFT4K schedule and store the result (replacing an earlier one); None for a
    schedule of another algorithm (no niceness)."""
    plan = schedule.to_engine()
    if not is_heft4k(plan):
        return None
    try:
        fields = simulate(plan, schedule.application.graph, schedule.engine_platform())
    except (InputError, KeyError) as exc:  # the application changed since: the page says so too
        fields = {"note": f"not simulated: {exc}"[:300]}
    defaults = {"note": "", "simulated": {}, "sharing": [], "baselines": [], **fields}
    with transaction.atomic():
        row, _ = ScheduleSimulation.objects.update_or_create(schedule=schedule, defaults=defaults)
    return row


def ensure(schedule: Schedule) -> ScheduleSimulation | None:
    """The stored simulation of ``schedule``, computed when there is none yet."""
    existing = ScheduleSimulation.objects.filter(schedule=schedule).first()
    return existing if existing is not None else store(schedule)


def on_schedule_stored(sender, schedule: Schedule, **kwargs) -> None:
    """Receiver of :data:`apps.scheduling.signals.schedule_stored`: the job that stored a HEFT4K schedule
    simulates it too."""
    progress = kwargs.get("progress")
    plan_has_niceness = schedule.assignments.filter(niceness__isnull=False).exists()
    if not plan_has_niceness:
        return
    if progress is not None:
        progress(98, "simulating the schedule on Kubernetes (Linux CFS)")
    store(schedule)
