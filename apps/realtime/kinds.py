"""The RT-Kube app's job kinds."""

from apps.jobs.registry import JobKind


class RealtimeJob(JobKind):
    RT_WHATIF = "rt_whatif"
    RT_SYNC = "rt_sync"
    RT_PUSH = "rt_push"
    RT_DELETE = "rt_delete"
    RT_REPORTS = "rt_reports"
