"""The clusters app's job kinds (node sync through the Kubernetes gateway, apps/clusters/jobs.py)."""

from apps.jobs.registry import JobKind


class ClusterJob(JobKind):
    SYNC_CLUSTER = "sync_cluster"
