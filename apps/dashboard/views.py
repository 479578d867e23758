"""The home page: what Continuum does, the three paths through it (each with its next step, or why it cannot
be taken yet and what to do about it), the live clusters' health and the recent jobs. It sits above every
domain app (each owns its pages: clusters, workloads, scheduling, containers, realtime, verification, jobs...)
and is the only page that reads them all."""

from __future__ import annotations

from dataclasses import dataclass

from django.contrib.auth.decorators import login_required
from django.db.models import Count, Q
from django.http import HttpRequest, HttpResponse
from django.shortcuts import render
from django.urls import reverse

from apps.clusters.models import Cluster, ComputeNode
from apps.containers.models import RosGraph
from apps.jobs.models import Job
from apps.realtime.models import RealTime
from apps.scheduling.models import Schedule
from apps.tenancy.scoping import visible_fleets
from apps.ui.helpers import scoped
from apps.verification.models import Assertion
from apps.workloads.models import Application

#: Clusters listed with their health on the home page (the clusters page lists them all).
HEALTH_CLUSTERS = 8


@dataclass(frozen=True)
class Step:
    """One next step of a path: a link, or (``reason`` set) a disabled button saying why and how to fix it."""

    label: str
    url: str
    reason: str = ""
    fix_url: str = ""
    fix_label: str = ""


def _step(label: str, url: str, missing: tuple[str, str, str] | None = None) -> Step:
    return Step(label, url) if missing is None else Step(label, url, *missing)


@login_required
def home(request: HttpRequest) -> HttpResponse:
    jobs = scoped(request, Job.objects.select_related("fleet", "created_by"))
    clusters = scoped(request, Cluster.objects).annotate(
        node_total=Count("nodes"),
        node_ready=Count("nodes", filter=Q(nodes__status=ComputeNode.Status.READY)),
        # NotReady and Unknown alike (apps.clusters.nodes: Ready is the only ready status).
        node_not_ready=Count("nodes", filter=~Q(nodes__status=ComputeNode.Status.READY)),
    )
    applications = scoped(request, Application.objects)
    counts = {
        "clusters": clusters.count(),
        "connected": clusters.exclude(kubeconfig="").count(),
        "nodes": scoped(request, ComputeNode.objects, "cluster__fleet").count(),
        "nodes_ready": scoped(request, ComputeNode.objects, "cluster__fleet").filter(status="Ready").count(),
        "applications": applications.count(),
        "schedules": scoped(request, Schedule.objects).count(),
        "rosgraphs": scoped(request, RosGraph.objects).count(),
        "realtime": scoped(request, RealTime.objects, "cluster__fleet").count(),
        "assertions": scoped(request, Assertion.objects).count(),
        "jobs_active": jobs.filter(state__in=[Job.State.PENDING, Job.State.RUNNING]).count(),
        "jobs_failed": jobs.filter(state=Job.State.FAILED).count(),
    }
    return render(
        request,
        "dashboard/home.html",
        {
            "counts": counts,
            "paths": _paths(counts, applications.order_by("-created").first()),
            "clusters": clusters.order_by("name")[:HEALTH_CLUSTERS],
            "recent_jobs": jobs[:10],
            "fleets": visible_fleets(request),
            "nav": "home",
        },
    )


def _paths(counts: dict[str, int], latest: Application | None) -> dict[str, list[Step]]:
    """The next steps of the three paths, each disabled with its reason while a prerequisite is missing."""
    clusters_url = reverse("clusters:clusters")
    no_cluster = ("no cluster yet", clusters_url + "#import", "import one")
    no_app = ("no application yet", reverse("workloads:applications") + "#upload", "upload a DAG")
    no_kube = ("no cluster has a Kubernetes API", clusters_url + "#import", "register a live cluster")
    no_graph = ("no ROS graph yet", reverse("containers:rosgraphs"), "upload one")
    app_url = reverse("workloads:application", args=[latest.pk]) if latest else ""
    return {
        "dag": [
            _step("Upload or generate a DAG", reverse("workloads:applications") + "#upload"),
            _step(
                f"Schedule {latest.name}" if latest else "Schedule an application",
                app_url + "#schedule",
                None if latest else no_app,
            ),
            _step("Compare algorithms", app_url + "#compare", None if latest else no_app),
            _step("Which board? (devices)", reverse("devices:devices")),
        ],
        "ros": [
            _step("Upload a ROS graph", reverse("containers:rosgraphs")),
            _step(
                "Cluster nodes into containers and place them",
                reverse("containers:rosgraphs"),
                None if counts["rosgraphs"] else no_graph,
            ),
            _step(
                "Remap with HEFT4K when a node fails",
                reverse("heft4k:remaps"),
                None if counts["clusters"] else no_cluster,
            ),
            _step("Push to Kubernetes", reverse("containers:rosgraphs"), None if counts["connected"] else no_kube),
        ],
        "rt": [
            _step(
                "RT-Kube: real-time pods",
                reverse("realtime:overview"),
                None if counts["clusters"] else no_cluster,
            ),
            _step("STL monitors and verification", reverse("verification:overview")),
            _step("Simulate assertion-based verification", reverse("verification:simulate")),
        ],
    }
