"""Job kinds of RT-Kube: ``rt_whatif`` (a placement over a set of containers) and ``rt_sync`` (the mirror)."""

from django.db import transaction

from apps.clusters.models import Cluster
from apps.jobs.registry import job_kind
from continuum.engine import rt_kube

from . import planning, sync
from .models import RTPlan


def _cluster(job) -> Cluster:
    pk = (job.arguments or {}).get("cluster")
    if not isinstance(pk, int) or isinstance(pk, bool):
        raise ValueError(f"argument 'cluster' must be the id of a cluster, got {pk!r}")
    cluster = Cluster.objects.filter(pk=pk, fleet=job.fleet).first()
    if cluster is None:
        raise ValueError(f"cluster {pk} does not exist")
    return cluster


@job_kind("rt_whatif")
def rt_whatif(job, progress) -> tuple[dict, str]:
    """Arguments: ``cluster``; ``realtimes`` (ids, default all) and/or ``containers`` (a continuum.rtset/v1
    document); ``params`` (k, b_score_argument, sort_tiebreak); ``with_bound`` (start from the bound pods)."""
    args = job.arguments or {}
    cluster = _cluster(job)
    progress(5, f"placing on {cluster.name}")
    plan = planning.whatif(
        cluster,
        realtime_ids=args.get("realtimes"),
        rtset=args.get("containers"),
        params=args.get("params"),
        with_bound=bool(args.get("with_bound", True)),
    )
    progress(90, "storing the plan")
    doc = {**plan.to_dict(), "explain": rt_kube.explain(plan)}
    with transaction.atomic():
        RTPlan.objects.filter(job=job).delete()  # a re-delivered job replaces its earlier result
        row = RTPlan.objects.create(
            cluster=cluster,
            kind=RTPlan.Kind.WHATIF,
            job=job,
            plan=doc,
            placed=len(doc["placements"]),
            pending=len(doc["pending"]),
        )
    return {"rt_plan": row.pk, "placed": row.placed, "pending": row.pending}, f"/api/v1/rt-plans/{row.pk}/"


@job_kind("rt_sync")
def rt_sync(job, progress) -> tuple[dict, str]:
    """Arguments: ``cluster``, ``namespace`` (optional, ``*`` = all). Installs the CRDs, mirrors node RT
    attributes, RealTime objects (both ways) and Monitoring counters."""
    cluster = _cluster(job)
    result = sync.full_sync(cluster, (job.arguments or {}).get("namespace"), progress)
    progress(100, "synced")
    return result, f"/api/v1/realtimes/?cluster={cluster.pk}"
