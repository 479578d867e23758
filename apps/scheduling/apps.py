from django.apps import AppConfig


class SchedulingConfig(AppConfig):
    name = "apps.scheduling"
    label = "scheduling"

    def ready(self) -> None:
        from . import (
            jobs,  # noqa: F401 - registers the job kinds
            views,
        )

        views.register()  # the schedule and compare forms and the schedules on the application page
