"""The scheduling app's job kinds (push_schedule's handler is the Kubernetes gateway's, apps/kube/jobs.py)."""

from apps.jobs.registry import JobKind, describe_kinds


class SchedulingJob(JobKind):
    SCHEDULE = "schedule"
    COMPARE = "compare"
    PUSH_SCHEDULE = "push_schedule"


describe_kinds(
    {
        SchedulingJob.SCHEDULE: "Schedule an application's DAG",
        SchedulingJob.COMPARE: "Compare scheduling algorithms on an application",
        SchedulingJob.PUSH_SCHEDULE: "Push a schedule's pods to Kubernetes",
    }
)
