"""Job kinds of RT-Kube: ``rt_whatif`` (a placement over a set of containers), ``rt_sync`` (the mirror), and
``rt_push``/``rt_delete`` (a RealTime written to or deleted from the API, out of the web request)."""

from datetime import datetime

from django.db import transaction

from apps.clusters.models import Cluster
from apps.jobs.registry import id_argument, job_kind, owned_row
from apps.realtime.kinds import RealtimeJob
from continuum.engine.rtkube import rt_kube

from . import monitoring, planning, sync
from .models import RealTime, RTPlan, RTPolicy


def _cluster(job) -> Cluster:
    return owned_row(job, Cluster.objects, "cluster")


@job_kind(RealtimeJob.RT_WHATIF)
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


@job_kind(RealtimeJob.RT_SYNC)
def rt_sync(job, progress) -> tuple[dict, str]:
    """Arguments: ``cluster``, ``namespace`` (optional, ``*`` = all). Installs the CRDs, mirrors node RT
    attributes, RealTime objects (both ways) and Monitoring counters."""
    cluster = _cluster(job)
    result = sync.full_sync(cluster, (job.arguments or {}).get("namespace"), progress)
    progress(100, "synced")
    return result, f"/api/v1/realtimes/?cluster={cluster.pk}"


def _realtimes(job, ids) -> list[RealTime]:
    if not isinstance(ids, list) or not ids or not all(isinstance(i, int) and not isinstance(i, bool) for i in ids):
        raise ValueError(f"argument 'realtimes' must be a non-empty list of RealTime ids, got {ids!r}")
    rows = list(RealTime.objects.select_related("cluster").filter(pk__in=ids, cluster__fleet=job.fleet))
    if not rows:
        raise ValueError(f"RealTime objects {ids} do not exist")
    return rows


@job_kind(RealtimeJob.RT_PUSH)
def rt_push(job, progress) -> tuple[dict, str]:
    """Arguments: ``realtimes`` (ids). Writes the rows to their cluster's Kubernetes API (create or replace);
    each row records its outcome (sync_state, sync_error). Runs as a job so that no web request calls
    Kubernetes. Fails, naming the rows and why, when any could not be written."""
    rows = _realtimes(job, (job.arguments or {}).get("realtimes"))
    failed = []
    for i, row in enumerate(rows, 1):
        if not sync.push_realtime(row):
            failed.append(f"{row.namespace}/{row.name}: {row.sync_error}")
        progress(100 * i / len(rows), f"pushed {i}/{len(rows)}")
    if failed:
        shown = "; ".join(failed)
        raise ValueError(f"{len(failed)} of {len(rows)} RealTime objects not written to Kubernetes: {shown}")
    return {"pushed": [r.pk for r in rows]}, f"/api/v1/realtimes/?cluster={rows[0].cluster_id}"


@job_kind(RealtimeJob.RT_DELETE)
def rt_delete(job, progress) -> tuple[dict, str]:
    """Arguments: ``realtime`` (id). Deletes its object from the Kubernetes API, then the row; when the API
    refuses, the row stays (with the reason in sync_error) and the job fails with it. Idempotent: a row gone
    already means done."""
    pk = id_argument(job, "realtime", what="RealTime")
    row = RealTime.objects.select_related("cluster").filter(pk=pk, cluster__fleet=job.fleet).first()
    if row is None:
        return {"deleted": pk, "already": True}, ""
    problem = sync.delete_realtime_object(row)
    if problem:
        RealTime.objects.filter(pk=row.pk).update(sync_state=RealTime.SyncState.ERROR, sync_error=problem[:500])
        raise ValueError(f"not deleted from Kubernetes: {problem}")
    row.delete()
    return {"deleted": pk}, f"/api/v1/realtimes/?cluster={row.cluster_id}"


@job_kind(RealtimeJob.RT_REPORTS)
def rt_reports(job, progress) -> tuple[dict, str]:
    """Arguments: ``cluster``, ``reports`` (Monitoring objects or specs), ``received_at`` (ISO 8601). Ingests a
    missed-deadline batch whose reconcile may call Kubernetes (eviction, taint), out of the web request.
    Eq. 3.19's response time still counts from when the request was received."""
    cluster = _cluster(job)
    args = job.arguments or {}
    try:
        received = datetime.fromisoformat(args.get("received_at") or "")
    except (TypeError, ValueError) as exc:
        raise ValueError(f"argument 'received_at' must be an ISO 8601 time, got {args.get('received_at')!r}") from exc
    reports = monitoring.parse_batch({"reports": args.get("reports")})
    try:
        policy = cluster.rt_policy
    except RTPolicy.DoesNotExist:
        policy = RTPolicy.for_cluster(cluster)
    result = monitoring.ingest(cluster, reports, policy=policy, received_at=received)
    progress(100, f"{result['accepted']} reports, {len(result['events'])} events")
    return result, f"/api/v1/rt-events/?cluster={cluster.pk}"
