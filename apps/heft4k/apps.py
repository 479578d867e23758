from django.apps import AppConfig


class Heft4kConfig(AppConfig):
    name = "apps.heft4k"
    label = "heft4k"
    verbose_name = "HEFT4K"

    def ready(self) -> None:
        # api: adds the schedules' remap action; jobs: registers the remap and remap_apply job kinds
        from . import api, jobs  # noqa: F401
