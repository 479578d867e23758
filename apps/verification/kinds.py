"""The verification app's job kinds."""

from apps.jobs.registry import JobKind


class VerificationJob(JobKind):
    ALLOCATE_MONITORS = "allocate_monitors"
    VERIFICATION_SIMULATION = "verification_simulation"
