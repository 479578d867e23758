"""The web app's ``/metrics`` (issue 28): for a Prometheus scraper holding ``CONTINUUM_METRICS_TOKEN``, nobody else.

- Not configured (no token): 404, as if the URL did not exist.
- Configured: ``Authorization: Bearer <token>`` (compared in constant time) gets the exposition; any other
  caller gets 401 with no body worth reading: a fleet's API token (``Token ...``), a dashboard session, an
  anonymous request. The figures are operational (jobs by state, nodes by status, requests per route) and
  span every fleet, so no fleet credential may read them.

Besides the process's own metrics (requests per route and their durations, counted by
:class:`RequestMetricsMiddleware`), each scrape counts jobs and nodes in the database (a few aggregate
queries): those figures are the same whichever gunicorn worker answers.
"""

from __future__ import annotations

import hmac
import time
from collections.abc import Callable, Iterator

from django.conf import settings
from django.db.models import Count
from django.http import HttpRequest, HttpResponse
from prometheus_client import CONTENT_TYPE_LATEST, CollectorRegistry, Counter, Histogram, generate_latest
from prometheus_client.core import GaugeMetricFamily
from prometheus_client.registry import Collector

from continuum.metrics import DURATION_BUCKETS, PREFIX, registry

REQUESTS = Counter(
    f"{PREFIX}_http_requests", "HTTP requests answered, by route and status", ["method", "route", "code"]
)
REQUEST_SECONDS = Histogram(
    f"{PREFIX}_http_request_duration_seconds",
    "Time to answer an HTTP request, by route",
    ["method", "route"],
    buckets=DURATION_BUCKETS,
)
METHODS = {"GET", "HEAD", "POST", "PUT", "PATCH", "DELETE", "OPTIONS"}


class DatabaseCollector(Collector):
    """Jobs by kind and state, compute nodes by status, and the not-ready alarm, counted at scrape time."""

    def collect(self) -> Iterator[GaugeMetricFamily]:
        from apps.clusters.models import ComputeNode
        from apps.jobs.models import Job

        jobs = GaugeMetricFamily(f"{PREFIX}_jobs", "Jobs in the database by kind and state", labels=["kind", "state"])
        for row in Job.objects.values("kind", "state").annotate(n=Count("pk")).order_by():
            jobs.add_metric([row["kind"], row["state"]], row["n"])
        yield jobs
        nodes = GaugeMetricFamily(
            f"{PREFIX}_nodes", "Compute nodes of Kubernetes clusters by status", labels=["status"]
        )
        down = 0
        for row in ComputeNode.objects.values("status").annotate(n=Count("pk")).order_by():
            nodes.add_metric([row["status"]], row["n"])
            down += row["n"] if row["status"] != ComputeNode.Status.READY else 0
        yield nodes
        yield GaugeMetricFamily(
            f"{PREFIX}_nodes_not_ready", "Compute nodes not Ready (NotReady or Unknown): the alarm", value=down
        )


def _authorized(request: HttpRequest, token: str) -> bool:
    scheme, _, given = request.headers.get("Authorization", "").partition(" ")
    return scheme.lower() == "bearer" and hmac.compare_digest(given.strip().encode(), token.encode())


def metrics_view(request: HttpRequest) -> HttpResponse:
    token = getattr(settings, "CONTINUUM_METRICS_TOKEN", "")
    if not token:
        return HttpResponse("Not Found\n", status=404, content_type="text/plain")
    if not _authorized(request, token):
        response = HttpResponse("Unauthorized\n", status=401, content_type="text/plain")
        response["WWW-Authenticate"] = 'Bearer realm="metrics"'
        return response
    database = CollectorRegistry(auto_describe=False)
    database.register(DatabaseCollector())
    body = generate_latest(registry()) + generate_latest(database)
    response = HttpResponse(body, content_type=CONTENT_TYPE_LATEST)
    response["Cache-Control"] = "no-store"
    return response


class RequestMetricsMiddleware:
    """Counts each request by method, route pattern (not the path: ids would make a series per object) and
    status, and times it."""

    def __init__(self, get_response: Callable[[HttpRequest], HttpResponse]) -> None:
        self.get_response = get_response

    def __call__(self, request: HttpRequest) -> HttpResponse:
        began = time.perf_counter()
        response = self.get_response(request)
        match = getattr(request, "resolver_match", None)
        route = (match.route or match.view_name or "") if match is not None else ""
        route = route.replace("^", "").rstrip("$") or "unmatched"  # a router's regex: api/v1/clusters/
        method = request.method if request.method in METHODS else "other"
        REQUEST_SECONDS.labels(method, route).observe(time.perf_counter() - began)
        REQUESTS.labels(method, route, str(response.status_code)).inc()
        return response
