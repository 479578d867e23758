"""Job handlers of the scheduling app."""

from django.conf import settings
from django.db import transaction

from apps.clusters.models import Cluster
from apps.jobs.registry import job_kind
from apps.workloads.models import Application
from continuum.engine import algorithms
from continuum.engine.platform import Platform

from .models import Schedule


def with_defaults(algorithm: str, params: dict) -> dict:
    """The algorithm's parameters with the deployment's defaults for readings the thesis leaves open."""
    params = dict(params)
    if algorithm == "heft":
        params.setdefault("rank_mode", settings.CONTINUUM_HEFT_RANK_MODE)
    return params


@job_kind("schedule")
def schedule_application(job, progress) -> tuple[dict, str]:
    """Arguments: application, algorithm, params, and either cluster (id) or platform (a document)."""
    args = job.arguments
    application = Application.objects.get(pk=args["application"], fleet=job.fleet)
    cluster = None
    if args.get("cluster") is not None:
        cluster = Cluster.objects.get(pk=args["cluster"], fleet=job.fleet)
        platform = cluster.to_platform()
    else:
        platform = Platform.from_dict(args["platform"])
    progress(1, "ranking tasks")
    dag = application.graph

    def report(done: int, total: int) -> None:
        progress(95 * done / max(total, 1), f"placed {done}/{total} tasks")

    params = with_defaults(args["algorithm"], args.get("params") or {})
    result = algorithms.run(args["algorithm"], dag, platform, progress=report, **params)
    progress(97, "storing the schedule")
    with transaction.atomic():
        row = Schedule.store(result, application=application, platform=platform, cluster=cluster, job=job)
    return {"schedule": row.pk, "makespan": row.makespan}, f"/api/v1/schedules/{row.pk}/"
