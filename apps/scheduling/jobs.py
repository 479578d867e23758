"""Job handlers of the scheduling app."""

from django.conf import settings
from django.db import transaction

from apps.clusters.models import Cluster
from apps.jobs.registry import job_kind, owned_row
from apps.scheduling.kinds import SchedulingJob
from apps.workloads.models import Application
from continuum.engine.core.platform import Platform
from continuum.engine.device import algorithms
from continuum.engine.device.compare import compare

from .models import Comparison, Schedule
from .signals import schedule_stored

FRAME_ARGUMENTS = ("frames", "fps", "period", "batch")


def with_defaults(algorithm: str, params: dict) -> dict:
    """The algorithm's parameters with the deployment's defaults for readings the thesis leaves open."""
    params = dict(params)
    if algorithm == "heft":
        params.setdefault("rank_mode", settings.CONTINUUM_HEFT_RANK_MODE)
    return params


def _target(job) -> tuple[Application, Cluster | None, Platform]:
    """The job's application and the cluster (its Ready nodes) or platform document it runs on."""
    application = owned_row(job, Application.objects, "application")
    cluster = owned_row(job, Cluster.objects, "cluster", required=False)
    platform = cluster.to_platform() if cluster is not None else Platform.from_dict(job.arguments["platform"])
    return application, cluster, platform


@job_kind(SchedulingJob.SCHEDULE)
def schedule_application(job, progress) -> tuple[dict, str]:
    """Arguments: application, algorithm, params (frames, fps... included), and either cluster (id) or
    platform (a document)."""
    args = job.arguments
    application, cluster, platform = _target(job)
    progress(1, "ranking tasks")
    dag = application.graph
    frames = (args.get("params") or {}).get("frames") or 1
    # Long pipelines report the frames too: "placed 4000/10000 tasks (10 frames)".
    suffix = f" ({frames} frames of {len(dag)} tasks)" if frames > 1 else ""

    def report(done: int, total: int) -> None:
        progress(1 + 94 * done / max(total, 1), f"placed {done}/{total} tasks{suffix}")

    params = with_defaults(args["algorithm"], args.get("params") or {})
    result = algorithms.run(args["algorithm"], dag, platform, progress=report, **params)
    progress(97, "storing the schedule")
    with transaction.atomic():
        row = Schedule.store(result, application=application, platform=platform, cluster=cluster, job=job)
    schedule_stored.send(sender=Schedule, schedule=row, progress=progress)
    return {"schedule": row.pk, "makespan": row.makespan}, f"/api/v1/schedules/{row.pk}/"


@job_kind(SchedulingJob.COMPARE)
def compare_algorithms(job, progress) -> tuple[dict, str]:
    """Arguments: application, algorithms, cluster or platform, optional frames/fps/period/batch, rank_mode,
    comm_mode. Stores each algorithm's schedule and a :class:`Comparison` with the figures side by side."""
    args = job.arguments
    application, cluster, platform = _target(job)
    names = list(args.get("algorithms") or [])
    dag = application.graph
    frame_args = {k: args[k] for k in FRAME_ARGUMENTS if args.get(k) is not None}
    modes = {k: args[k] for k in ("rank_mode", "comm_mode") if args.get(k)}
    progress(1, f"comparing {len(names)} algorithms")

    def report(name: str, index: int, count: int, done: int, total: int) -> None:
        fraction = done / total if total else 0.0
        step = f"placed {done}/{total} tasks" if total else "ranking tasks"
        progress(1 + 94 * (index + fraction) / count, f"{name} ({index + 1}/{count}): {step}")

    made = {}
    result = compare(dag, platform, names, progress=report, on_schedule=made.__setitem__, **frame_args, **modes)
    progress(96, "storing the schedules")
    with transaction.atomic():
        Comparison.objects.filter(job=job).delete()  # an earlier attempt's, with its schedules
        comparison = Comparison.objects.create(
            fleet=job.fleet,
            application=application,
            cluster=cluster,
            job=job,
            platform=platform.to_dict(),
            algorithms=names,
            params=result["params"] | {"frames": result["frames"]},
            result=result,
            best=result["best"],
        )
        stored = [
            Schedule.store(
                made[name], application=application, platform=platform, cluster=cluster, comparison=comparison
            )
            for name in names
        ]
    for row in stored:
        schedule_stored.send(sender=Schedule, schedule=row, progress=progress)
    summary = {
        "comparison": comparison.pk,
        "best": result["best"],
        "makespan": {name: row["makespan"] for name, row in result["results"].items()},
    }
    return summary, f"/api/v1/comparisons/{comparison.pk}/"
