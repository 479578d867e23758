"""The verification app's job kinds."""

from apps.jobs.registry import JobKind, describe_kinds


class VerificationJob(JobKind):
    ALLOCATE_MONITORS = "allocate_monitors"
    VERIFICATION_SIMULATION = "verification_simulation"


describe_kinds(
    {
        VerificationJob.ALLOCATE_MONITORS: "Allocate STL monitors to nodes (MILP)",
        VerificationJob.VERIFICATION_SIMULATION: "Simulate assertion-based verification on a case study",
    }
)
