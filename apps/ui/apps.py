from django.apps import AppConfig


class UiConfig(AppConfig):
    """The shared UI kit: layout and chart helpers, pagination and fleet scoping, template tags, the base
    templates and the panel registry. It imports no domain app (only ``apps.tenancy`` for scoping)."""

    name = "apps.ui"
    label = "ui"
    verbose_name = "UI kit"
