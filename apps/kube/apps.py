from django.apps import AppConfig


class KubeConfig(AppConfig):
    name = "apps.kube"
    label = "kube"
