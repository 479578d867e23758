"""The containers app's job kinds (ROS clustering, placement, pushing a placement)."""

from apps.jobs.registry import JobKind, describe_kinds


class ContainersJob(JobKind):
    CLUSTER_ROS = "cluster_ros"
    PLACE = "place"
    PUSH_PLACEMENT = "push_placement"
    BUILD_IMAGES = "build_images"


describe_kinds(
    {
        ContainersJob.CLUSTER_ROS: "Cluster a ROS graph's nodes into containers",
        ContainersJob.PLACE: "Place containers on a cluster's nodes",
        ContainersJob.PUSH_PLACEMENT: "Push a placement to Kubernetes as Deployments",
        ContainersJob.BUILD_IMAGES: "Build a clustering's images by inheritance with buildah and measure them",
    }
)
