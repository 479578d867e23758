from django.apps import AppConfig


class ClustersConfig(AppConfig):
    name = "apps.clusters"
    label = "clusters"

    def ready(self) -> None:
        from apps.ui.links import register_object_names, register_object_page

        from .models import Cluster

        # Job pages link the rows a job's arguments name to their pages.
        register_object_page("cluster", "clusters:cluster")
        register_object_names("cluster", Cluster)  # job rows and pages show its name, and a search finds it
        from apps.tenancy.demo import register_demo

        from . import jobs  # noqa: F401 - registers the sync_cluster job kind
        from .demo import demo_cluster

        register_demo(demo_cluster)
