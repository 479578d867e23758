from django.contrib import admin
from django.contrib.auth import views as auth_views
from django.contrib.auth.views import redirect_to_login
from django.http import HttpRequest, HttpResponse, HttpResponseServerError
from django.template import loader
from django.urls import include, path
from drf_spectacular.views import SpectacularAPIView, SpectacularRedocView, SpectacularSwaggerSplitView
from rest_framework.routers import DefaultRouter

from apps.clusters.api import ClusterViewSet, ComputeNodeViewSet, LinkViewSet
from apps.containers.api import ClusteringViewSet, PlacementViewSet, RosGraphViewSet
from apps.devices.api import DeviceProfileViewSet
from apps.heft4k.api import RemapEventViewSet
from apps.jobs.api import JobViewSet
from apps.realtime.api import register_routes as register_realtime
from apps.scheduling.api import ComparisonViewSet, ScheduleViewSet
from apps.tenancy.api import FleetViewSet
from apps.tenancy.login import ThrottledLoginView
from apps.verification.api import (
    AllocationRunViewSet,
    AssertionViewSet,
    EventViewSet,
    HandlerViewSet,
    MigrationEventViewSet,
    MonitorViewSet,
    VerdictViewSet,
    ViolationViewSet,
)
from apps.workloads.api import ApplicationViewSet
from continuum.web_metrics import metrics_view

router = DefaultRouter()
router.register("fleets", FleetViewSet)
router.register("clusters", ClusterViewSet)
router.register("nodes", ComputeNodeViewSet)
router.register("links", LinkViewSet)
router.register("applications", ApplicationViewSet)
router.register("schedules", ScheduleViewSet)
router.register("comparisons", ComparisonViewSet)
router.register("jobs", JobViewSet)
router.register("rosgraphs", RosGraphViewSet)
router.register("clusterings", ClusteringViewSet)
router.register("placements", PlacementViewSet)
router.register("remaps", RemapEventViewSet)
register_realtime(router)
router.register("devices", DeviceProfileViewSet)
router.register("assertions", AssertionViewSet)
router.register("monitors", MonitorViewSet)
router.register("handlers", HandlerViewSet)
router.register("violations", ViolationViewSet)
router.register("verdicts", VerdictViewSet)
router.register("events", EventViewSet, basename="event")
router.register("allocations", AllocationRunViewSet)
router.register("migrations", MigrationEventViewSet)


def browsable_docs(view):
    """An API reference page for browsers: a visitor not logged in is sent to the login page and back (the
    docs needed a session and answered a bare 401; a client with a token still reaches the view)."""

    def docs(request: HttpRequest, *args, **kwargs) -> HttpResponse:
        if not request.user.is_authenticated and "HTTP_AUTHORIZATION" not in request.META:
            return redirect_to_login(request.get_full_path())
        return view(request, *args, **kwargs)

    return docs


def server_error(request: HttpRequest) -> HttpResponse:
    """The 500 page with the navigation when the request's user can still be read; without it when the error
    is one that reading the user would repeat (the database gone)."""
    template = loader.get_template("500.html")
    try:
        body = template.render({}, request)
    except Exception:  # the page must render whatever broke the request
        body = template.render({})
    return HttpResponseServerError(body)


handler500 = server_error

urlpatterns = [
    path("api/v1/", include((router.urls, "api"))),
    path("api/schema/", SpectacularAPIView.as_view(), name="schema"),
    # The split view serves its start-up script as a file: no inline script (Content-Security-Policy).
    path("api/docs/", browsable_docs(SpectacularSwaggerSplitView.as_view(url_name="schema")), name="api-docs"),
    path("api/redoc/", browsable_docs(SpectacularRedocView.as_view(url_name="schema")), name="api-redoc"),
    path("metrics", metrics_view, name="metrics"),
    path("admin/", admin.site.urls),
    path("login/", ThrottledLoginView.as_view(), name="login"),
    path("logout/", auth_views.LogoutView.as_view(), name="logout"),
    path("ros/", include("apps.containers.urls")),
    path("realtime/", include("apps.realtime.urls")),
    path("", include("apps.dashboard.urls")),
    path("", include("apps.clusters.urls")),
    path("", include("apps.workloads.urls")),
    path("", include("apps.scheduling.urls")),
    path("", include("apps.devices.urls")),
    path("", include("apps.jobs.urls")),
    path("", include("apps.heft4k.urls")),
    path("verification/", include("apps.verification.urls")),
]
