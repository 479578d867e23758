from django.apps import AppConfig


class ContainersConfig(AppConfig):
    name = "apps.containers"
    label = "containers"
    verbose_name = "ROS graphs, containers and placements"

    def ready(self) -> None:
        from . import jobs  # noqa: F401 - registers the cluster_ros, place and push_placement job kinds
