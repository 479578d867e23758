from django.apps import AppConfig


class JobsConfig(AppConfig):
    name = "apps.jobs"
    label = "jobs"

    def ready(self) -> None:
        # Configure the Celery app in every process that runs Django, so that .delay() works both in
        # the eager quick start and against a broker.
        import continuum.celery  # noqa: F401
