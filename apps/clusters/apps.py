from django.apps import AppConfig


class ClustersConfig(AppConfig):
    name = "apps.clusters"
    label = "clusters"

    def ready(self) -> None:
        from apps.tenancy.demo import register_demo

        from .demo import demo_cluster

        register_demo(demo_cluster)
