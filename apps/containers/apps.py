from django.apps import AppConfig


class ContainersConfig(AppConfig):
    name = "apps.containers"
    label = "containers"
    verbose_name = "ROS graphs, containers and placements"

    def ready(self) -> None:
        from apps.ui.links import register_object_page

        # Job pages link the rows a job's arguments name to their pages.
        register_object_page("rosgraph", "containers:rosgraph")
        register_object_page("clustering", "containers:clustering")
        register_object_page("placement", "containers:placement")
        from django.core import checks

        from apps.clusters.live import register_pod_handler

        from .resources import check_clustering_method, check_resource_model

        checks.register(check_resource_model)
        checks.register(check_clustering_method)

        from . import jobs  # noqa: F401 - registers the cluster_ros, place and push_placement job kinds
        from .live import store_pod_state

        register_pod_handler("containers", store_pod_state)  # the live state of its pods (watch_cluster)
