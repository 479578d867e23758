"""The clusters app's job kinds (sync_cluster's handler is the Kubernetes gateway's, apps/kube/jobs.py)."""

from apps.jobs.registry import JobKind


class ClusterJob(JobKind):
    SYNC_CLUSTER = "sync_cluster"
