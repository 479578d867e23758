"""Job handlers of the Kubernetes gateway: ``sync_cluster`` and ``push_schedule``."""

from apps.clusters.kinds import ClusterJob
from apps.clusters.models import Cluster
from apps.jobs.registry import job_kind
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.models import Schedule

from . import gateway


def _argument(job, name: str) -> int:
    value = (job.arguments or {}).get(name)
    if not isinstance(value, int) or isinstance(value, bool):
        raise ValueError(f"argument {name!r} must be the id of a {name}, got {value!r}")
    return value


@job_kind(ClusterJob.SYNC_CLUSTER)
def sync_cluster(job, progress) -> tuple[dict, str]:
    """Arguments: ``cluster`` (id). Reads the nodes of the cluster's Kubernetes API into its ComputeNodes."""
    pk = _argument(job, "cluster")
    cluster = Cluster.objects.filter(pk=pk, fleet=job.fleet).first()
    if cluster is None:
        raise ValueError(f"cluster {pk} does not exist")
    progress(1, f"reading the nodes of {cluster.name}")
    counts = gateway.sync_nodes(cluster, progress)
    progress(100, f"{counts['nodes']} nodes synced")
    return {"cluster": cluster.pk, **counts}, f"/api/v1/clusters/{cluster.pk}/"


@job_kind(SchedulingJob.PUSH_SCHEDULE)
def push_schedule(job, progress) -> tuple[dict, str]:
    """Arguments: ``schedule`` (id). Creates one pod per assignment and binds it to the assigned node."""
    pk = _argument(job, "schedule")
    schedule = Schedule.objects.select_related("cluster", "application").filter(pk=pk, fleet=job.fleet).first()
    if schedule is None:
        raise ValueError(f"schedule {pk} does not exist")
    progress(1, f"pushing schedule {schedule.pk} to {schedule.cluster or 'no cluster'}")
    summary = gateway.push_schedule(schedule, progress)
    return summary, f"/api/v1/schedules/{schedule.pk}/"
