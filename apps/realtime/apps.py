from django.apps import AppConfig


class RealtimeConfig(AppConfig):
    name = "apps.realtime"
    label = "realtime"
    verbose_name = "Real-time (RT-Kube)"

    def ready(self) -> None:
        from . import jobs  # noqa: F401 - registers the rt_whatif and rt_sync job kinds
