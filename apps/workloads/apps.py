from django.apps import AppConfig


class WorkloadsConfig(AppConfig):
    name = "apps.workloads"
    label = "workloads"

    def ready(self) -> None:
        from apps.tenancy.demo import register_demo

        from .demo import demo_applications

        register_demo(demo_applications)
