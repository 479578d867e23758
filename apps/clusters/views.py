"""Cluster pages: the list and one cluster's nodes, links and network figure. Login required, fleet-scoped."""

from __future__ import annotations

from django.contrib.auth.decorators import login_required
from django.db.models import Count, Q
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, render

from apps.ui import charts
from apps.ui.helpers import paginate, scoped

from .models import Cluster


@login_required
def cluster_list(request: HttpRequest) -> HttpResponse:
    clusters = (
        scoped(request, Cluster.objects.select_related("fleet"))
        .annotate(
            node_count=Count("nodes", distinct=True),
            ready_count=Count("nodes", filter=Q(nodes__status="Ready"), distinct=True),
            link_count=Count("links", distinct=True),
        )
        .order_by("name", "pk")
    )
    return render(request, "clusters/cluster_list.html", {"page": paginate(request, clusters), "nav": "clusters"})


@login_required
def cluster_detail(request: HttpRequest, pk: int) -> HttpResponse:
    cluster = get_object_or_404(scoped(request, Cluster.objects.select_related("fleet")), pk=pk)
    nodes = list(cluster.nodes.all())
    links = list(cluster.links.select_related("src", "dst"))
    figure = None
    if nodes:
        platform = cluster.to_platform(ready_only=False)
        fig = charts.network_figure(
            platform,
            status={n.name: n.status for n in nodes},
            bandwidth_scale=1000.0,  # the cluster platform stores Mbit per ms
            bandwidth_unit="Mbit/s",
            latency_unit="ms",
        )
        figure = charts.to_html(fig, div_id="network-chart")
    return render(
        request,
        "clusters/cluster_detail.html",
        {
            "cluster": cluster,
            "nodes": nodes,
            "links": links,
            "figure": figure,
            "schedules": cluster.schedules.select_related("application")[:10],
            "nav": "clusters",
        },
    )
