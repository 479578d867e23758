from django.apps import AppConfig


class DashboardConfig(AppConfig):
    """The home page, above every domain app (each owns its pages; the shared kit is ``apps.ui``)."""

    name = "apps.dashboard"
    label = "dashboard"
