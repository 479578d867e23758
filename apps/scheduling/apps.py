from django.apps import AppConfig


class SchedulingConfig(AppConfig):
    name = "apps.scheduling"
    label = "scheduling"

    def ready(self) -> None:
        from . import jobs, kube  # noqa: F401 - register the job kinds (kube: push_schedule)
