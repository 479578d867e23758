"""The RT-Kube app's job kinds."""

from apps.jobs.registry import JobKind, describe_kinds


class RealtimeJob(JobKind):
    RT_WHATIF = "rt_whatif"
    RT_SYNC = "rt_sync"
    RT_PUSH = "rt_push"
    RT_DELETE = "rt_delete"
    RT_REPORTS = "rt_reports"


describe_kinds(
    {
        RealtimeJob.RT_WHATIF: "Try RT-Kube's placement of real-time pods (what-if)",
        RealtimeJob.RT_SYNC: "Synchronise RT-Kube objects with a cluster's Kubernetes API",
        RealtimeJob.RT_PUSH: "Write RealTime objects to Kubernetes",
        RealtimeJob.RT_DELETE: "Delete a RealTime object from Kubernetes",
        RealtimeJob.RT_REPORTS: "Ingest a batch of missed-deadline reports",
    }
)
