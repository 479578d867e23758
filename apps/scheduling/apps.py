from django.apps import AppConfig


class SchedulingConfig(AppConfig):
    name = "apps.scheduling"
    label = "scheduling"

    def ready(self) -> None:
        from apps.tenancy.demo import register_demo

        # api: adds the applications' schedule and compare actions; jobs: registers the job kinds (kube: push_schedule)
        from . import api, jobs, kube, views  # noqa: F401
        from .demo import demo_schedule

        register_demo(demo_schedule)
        views.register()  # the schedule and compare forms and the schedules on the application page

        from apps.clusters.live import register_pod_handler

        from .live import store_pod_state

        register_pod_handler("scheduling", store_pod_state)  # the live state of its pods (watch_cluster)
