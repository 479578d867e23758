"""The scheduling app's job kinds (push_schedule's handler is the Kubernetes gateway's, apps/kube/jobs.py)."""

from apps.jobs.registry import JobKind


class SchedulingJob(JobKind):
    SCHEDULE = "schedule"
    COMPARE = "compare"
    PUSH_SCHEDULE = "push_schedule"
