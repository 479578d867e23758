"""The containers app's job kinds (ROS clustering, placement, pushing a placement)."""

from apps.jobs.registry import JobKind


class ContainersJob(JobKind):
    CLUSTER_ROS = "cluster_ros"
    PLACE = "place"
    PUSH_PLACEMENT = "push_placement"
