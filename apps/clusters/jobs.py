"""Job handlers of the clusters app: ``sync_cluster`` (read a cluster's nodes from its Kubernetes API)."""

from apps.clusters.kinds import ClusterJob
from apps.jobs.registry import job_kind, owned_row

from . import kube
from .models import Cluster


@job_kind(ClusterJob.SYNC_CLUSTER)
def sync_cluster(job, progress) -> tuple[dict, str]:
    """Arguments: ``cluster`` (id). Reads the nodes of the cluster's Kubernetes API into its ComputeNodes."""
    cluster = owned_row(job, Cluster.objects, "cluster")
    progress(1, f"reading the nodes of {cluster.name}")
    counts = kube.sync_nodes(cluster, progress)
    progress(100, f"{counts['nodes']} nodes synced")
    return {"cluster": cluster.pk, **counts}, f"/api/v1/clusters/{cluster.pk}/"
