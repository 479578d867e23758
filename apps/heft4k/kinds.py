"""The HEFT4K app's job kinds (remapping after node failures, Algorithm 2)."""

from apps.jobs.registry import JobKind


class Heft4kJob(JobKind):
    REMAP = "remap"
    REMAP_APPLY = "remap_apply"
    SIMULATE = "heft4k_simulate"  # the CFS simulation and baselines of a schedule stored before they were
