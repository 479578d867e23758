"""The clusters app's job kinds (node sync through the Kubernetes gateway, apps/clusters/jobs.py)."""

from apps.jobs.registry import JobKind, describe_kinds


class ClusterJob(JobKind):
    SYNC_CLUSTER = "sync_cluster"


describe_kinds(
    {
        ClusterJob.SYNC_CLUSTER: "Read a cluster's nodes from its Kubernetes API",
    }
)
