"""Job handlers of HEFT4K remapping: ``remap`` (compute, and apply unless a what-if) and ``remap_apply``."""

from apps.heft4k.kinds import Heft4kJob
from apps.jobs.registry import job_kind, owned_row
from apps.scheduling.models import Schedule
from continuum.engine.core.errors import InputError

from . import remapping, simulation
from .models import RemapEvent


@job_kind(Heft4kJob.REMAP)
def remap(job, progress) -> tuple[dict, str]:
    """Arguments: ``schedule`` (id), ``fail`` (node names), ``what_if`` (bool), ``threshold`` (fraction or
    null for the deployment's default), ``trigger`` ("api", "what-if" or "watch").

    Runs Algorithm 2 and stores the new schedule and the remap event; unless ``what_if``, pushes the pods
    that change. A re-delivered job finds its event and only (re)applies it.
    """
    args = job.arguments or {}
    event = RemapEvent.objects.filter(job=job).select_related("schedule", "new_schedule").first()
    if event is None:
        schedule = owned_row(job, Schedule.objects.select_related("application", "cluster"), "schedule")
        fail = args.get("fail")
        if not isinstance(fail, list):
            raise InputError(f"argument 'fail' must be a list of node names, got {fail!r}", "fail")
        trigger = args.get("trigger") or (RemapEvent.Trigger.WHAT_IF if args.get("what_if") else RemapEvent.Trigger.API)
        if trigger not in RemapEvent.Trigger.values:
            raise InputError(f"unknown trigger {trigger!r}", "trigger")
        progress(5, f"remapping schedule {schedule.pk} without {', '.join(map(str, fail))}")
        event = remapping.compute(schedule, fail, threshold=args.get("threshold"), trigger=trigger, job=job)
    if event.new_schedule is not None:
        simulation.ensure(event.new_schedule)  # what the new schedule's page shows beside the plan
    progress(
        50,
        f"{event.decision} remap: {len(event.lost_tasks)} tasks lost, {len(event.moved_tasks)} moved, "
        f"computed in {event.elapsed_ms:.1f} ms",
    )
    if not args.get("what_if"):
        remapping.apply(event, progress)
    return remapping.summary(event), f"/api/v1/remaps/{event.pk}/"


@job_kind(Heft4kJob.REMAP_APPLY)
def remap_apply(job, progress) -> tuple[dict, str]:
    """Arguments: ``remap`` (id of a what-if remap event). Pushes the pods its new schedule changes."""
    event = owned_row(job, RemapEvent.objects.select_related("schedule", "new_schedule"), "remap")
    progress(5, f"applying remap {event.pk}")
    remapping.apply(event, progress)
    return remapping.summary(event), f"/api/v1/remaps/{event.pk}/"


@job_kind(Heft4kJob.SIMULATE)
def simulate(job, progress) -> tuple[dict, str]:
    """Arguments: ``schedule`` (id of a HEFT4K schedule). Runs its CFS simulation and the baselines and stores
    them for the schedule page (schedules stored before the jobs did it themselves)."""
    schedule = owned_row(job, Schedule.objects.select_related("application"), "schedule")
    progress(5, f"simulating schedule {schedule.pk} on Kubernetes (Linux CFS)")
    row = simulation.store(schedule)
    if row is None:
        raise InputError(f"schedule {schedule.pk} is not a HEFT4K schedule (its tasks have no niceness)", "schedule")
    result = {"schedule": schedule.pk, "simulated": not row.note, "note": row.note}
    return result, f"/api/v1/schedules/{schedule.pk}/"
