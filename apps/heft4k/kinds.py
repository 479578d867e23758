"""The HEFT4K app's job kinds (remapping after node failures, Algorithm 2)."""

from apps.jobs.registry import JobKind, describe_kinds


class Heft4kJob(JobKind):
    REMAP = "remap"
    REMAP_APPLY = "remap_apply"
    SIMULATE = "heft4k_simulate"  # the CFS simulation and baselines of a schedule stored before they were


describe_kinds(
    {
        Heft4kJob.REMAP: "Remap a schedule with HEFT4K after node failures",
        Heft4kJob.REMAP_APPLY: "Apply a what-if remap to Kubernetes",
        Heft4kJob.SIMULATE: "Simulate a HEFT4K schedule under CFS against the baselines",
    }
)
