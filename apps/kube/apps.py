from django.apps import AppConfig


class KubeConfig(AppConfig):
    name = "apps.kube"
    label = "kube"

    def ready(self) -> None:
        from . import jobs  # noqa: F401 - registers the sync_cluster and push_schedule job kinds
