from django.apps import AppConfig


class WorkloadsConfig(AppConfig):
    name = "apps.workloads"
    label = "workloads"

    def ready(self) -> None:
        from apps.ui.links import register_object_page

        # Job pages link the rows a job's arguments name to their pages.
        register_object_page("application", "workloads:application")
        from apps.tenancy.demo import register_demo

        from .demo import demo_applications

        register_demo(demo_applications)
