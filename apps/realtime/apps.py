from django.apps import AppConfig


class RealtimeConfig(AppConfig):
    name = "apps.realtime"
    label = "realtime"
    verbose_name = "Real-time (RT-Kube)"

    def ready(self) -> None:
        from apps.clusters.live import register_pod_handler
        from apps.ui.links import register_result_page

        from . import jobs  # noqa: F401 - registers the rt_whatif and rt_sync job kinds
        from .live import store_pod_state

        # Its rows are mirrored from the API (namespace, name, uid): every namespace the RT scheduler serves.
        register_pod_handler("realtime", store_pod_state, any_namespace=True)  # live state (the cluster agent)
        # A what-if job's "Open the result" goes to its plan's page, not the plan's API JSON (issue 30).
        register_result_page("rt_plan", "realtime:plan", order=15)
