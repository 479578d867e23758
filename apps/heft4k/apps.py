from django.apps import AppConfig


class Heft4kConfig(AppConfig):
    name = "apps.heft4k"
    label = "heft4k"
    verbose_name = "HEFT4K"

    def ready(self) -> None:
        from apps.clusters.nodes import register_node_handler
        from apps.scheduling.signals import schedule_stored

        # api: adds the schedules' remap action; jobs: registers the remap, remap_apply and heft4k_simulate kinds
        from . import api, jobs, simulation, views, watch  # noqa: F401

        views.register()  # HEFT4K's panels on the schedule and application pages
        register_node_handler("heft4k-remap", watch.remap_trigger)  # Algorithm 2's trigger, in the cluster agent
        schedule_stored.connect(simulation.on_schedule_stored, dispatch_uid="heft4k-simulate-stored-schedules")
