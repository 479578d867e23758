from django.apps import AppConfig


class WorkloadsConfig(AppConfig):
    name = "apps.workloads"
    label = "workloads"

    def ready(self) -> None:
        from apps.ui.links import register_object_names, register_object_page

        from .models import Application

        # Job pages link the rows a job's arguments name to their pages.
        register_object_page("application", "workloads:application")
        register_object_names("application", Application)  # job rows and pages show its name, and a search finds it
        from apps.tenancy.demo import register_demo

        from .demo import demo_applications

        register_demo(demo_applications)
