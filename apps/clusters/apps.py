from django.apps import AppConfig


class ClustersConfig(AppConfig):
    name = "apps.clusters"
    label = "clusters"

    def ready(self) -> None:
        from apps.tenancy.demo import register_demo

        from . import jobs  # noqa: F401 - registers the sync_cluster job kind
        from .demo import demo_cluster

        register_demo(demo_cluster)
