from django.apps import AppConfig


class KubeConfig(AppConfig):
    """The Kubernetes gateway (no models, no jobs: the apps owning the rows register the jobs that use it)."""

    name = "apps.kube"
    label = "kube"
