from django.apps import AppConfig


class Heft4kConfig(AppConfig):
    name = "apps.heft4k"
    label = "heft4k"
    verbose_name = "HEFT4K"

    def ready(self) -> None:
        from . import jobs  # noqa: F401 - registers the remap and remap_apply job kinds
