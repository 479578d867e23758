from django.apps import AppConfig


class VerificationConfig(AppConfig):
    name = "apps.verification"
    label = "verification"
    verbose_name = "Assertion-based verification"

    def ready(self) -> None:
        from . import jobs  # noqa: F401 - registers the allocate_monitors and verification_simulation job kinds
