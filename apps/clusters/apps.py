from django.apps import AppConfig


class ClustersConfig(AppConfig):
    name = "apps.clusters"
    label = "clusters"

    def ready(self) -> None:
        from . import jobs  # noqa: F401 - registers the sync_cluster job kind
