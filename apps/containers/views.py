"""Dashboard pages of ROS graphs -> containers -> nodes. Every page needs a login and shows only the user's
fleets' objects (another fleet's answers 404)."""

from __future__ import annotations

from django.contrib import messages
from django.contrib.auth.decorators import login_required
from django.db import transaction
from django.db.models import Count
from django.http import Http404, HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, redirect, render
from django.views.decorators.http import require_POST

from apps.containers.kinds import ContainersJob
from apps.jobs.registry import HANDLERS
from apps.jobs.services import start_job
from apps.tenancy.scoping import visible_fleets
from apps.ui.charts import to_html
from apps.ui.helpers import paginate, scoped
from continuum.engine.containers.superclustering import container_bandwidth
from continuum.engine.core.errors import InputError

from . import charts, services
from .forms import ClusterForm, LevelsForm, PlaceForm, RosGraphUploadForm
from .models import Clustering, ContainerDeployment, Placement, RosGraph

NAV = "ros"


# ---- ROS graphs -------------------------------------------------------------------------------------------
@login_required
def rosgraph_list(request: HttpRequest) -> HttpResponse:
    fleets = visible_fleets(request)
    bound = request.method == "POST"
    form = RosGraphUploadForm(request.POST if bound else None, request.FILES if bound else None, fleets=fleets)
    status = 200
    if bound:
        if form.is_valid():
            row = form.save(request.user)
            messages.success(request, f"Imported {row.name!r}: {row.node_count} ROS nodes, {row.topic_count} topics.")
            return redirect("containers:rosgraph", pk=row.pk)
        status = 400
    graphs = (
        scoped(request, RosGraph.objects.select_related("fleet"))
        .annotate(clustering_count=Count("clusterings"))
        .order_by("-created", "-pk")
    )
    return render(
        request,
        "containers/rosgraph_list.html",
        {"page": paginate(request, graphs), "form": form, "has_fleet": fleets.exists(), "nav": NAV},
        status=status,
    )


def _graph_page(request, row: RosGraph, *, cluster_form=None, levels_form=None, status: int = 200) -> HttpResponse:
    graph = row.graph
    clusterings = list(row.clusterings.order_by("-created", "-pk")[:20])
    shown = None
    wanted = request.GET.get("clustering")
    if wanted and wanted.isdigit():
        shown = next((c for c in clusterings if c.pk == int(wanted)), None)
    elif clusterings:
        shown = clusterings[0]
    # The stored snapshot may predate an edit that changed nothing structural; colour only if it still fits.
    groups = shown.groups() if shown and set(graph.nodes) == {n for ms in shown.groups().values() for n in ms} else None
    proposed = graph.levels()
    level_rows = [
        {"name": n, "level": proposed[n], "given": bool(node.level), "cpu": node.cpu, "memory_mib": node.memory_mib}
        for n, node in sorted(graph.nodes.items())
    ]
    topics = sorted(graph.topics.values(), key=lambda t: t.name)
    levels_form = levels_form or LevelsForm(graph=graph)
    return render(
        request,
        "containers/rosgraph_detail.html",
        {
            "row": row,
            "graph": graph,
            "figure": to_html(charts.rosgraph_figure(graph, groups), div_id="rosgraph-chart"),
            "shown": shown if groups else None,
            "clusterings": clusterings,
            "level_fields": [(levels_form[f"level:{r['name']}"], r) for r in level_rows],
            "topics": [
                {
                    "name": t.name,
                    "publishers": t.publishers,
                    "subscribers": t.subscribers,
                    "rates": sorted(set(t.rates.values())),
                    "msg_bytes": t.msg_bytes,
                    "bps": sum(t.rate(p) for p in t.publishers) * t.msg_bytes * len(t.subscribers),
                }
                for t in topics
            ],
            "cluster_form": cluster_form or ClusterForm(initial={"containers": min(4, max(1, len(graph.nodes)))}),
            "levels_form": levels_form,
            "nav": NAV,
        },
        status=status,
    )


@login_required
def rosgraph_detail(request: HttpRequest, pk: int) -> HttpResponse:
    row = get_object_or_404(scoped(request, RosGraph.objects.select_related("fleet")), pk=pk)
    return _graph_page(request, row)


@login_required
@require_POST
def rosgraph_levels(request: HttpRequest, pk: int) -> HttpResponse:
    row = get_object_or_404(scoped(request, RosGraph.objects.select_related("fleet")), pk=pk)
    form = LevelsForm(request.POST, graph=row.graph)
    if not form.is_valid():
        return _graph_page(request, row, levels_form=form, status=400)
    try:
        graph = services.edit_graph(row.document, levels=form.levels())
    except InputError as exc:
        form.add_error(None, str(exc))
        return _graph_page(request, row, levels_form=form, status=400)
    with transaction.atomic():
        row.set_graph(graph)
        row.save()
    messages.success(request, "Levels saved.")
    return redirect("containers:rosgraph", pk=row.pk)


@login_required
@require_POST
def rosgraph_cluster(request: HttpRequest, pk: int) -> HttpResponse:
    row = get_object_or_404(scoped(request, RosGraph.objects.select_related("fleet")), pk=pk)
    form = ClusterForm(request.POST)
    if not form.is_valid():
        return _graph_page(request, row, cluster_form=form, status=400)
    job = start_job(ContainersJob.CLUSTER_ROS, row.fleet, form.job_arguments(row), request.user)
    return redirect("jobs:job", pk=job.pk)


# ---- clusterings ------------------------------------------------------------------------------------------
def _clustering_page(request, clustering: Clustering, form: PlaceForm | None = None, status: int = 200):
    graph = clustering.graph
    groups = clustering.groups()
    mode = clustering.result.get("params", {}).get("mode", "per_topic")
    bandwidth = [
        {"a": a, "b": b, "bytes_per_s": w} for (a, b), w in sorted(container_bandwidth(graph, groups, mode).items())
    ]
    levels = graph.levels()
    rows = []
    for c in clustering.containers:
        rows.append(
            {
                "name": c["name"],
                "nodes": c["nodes"],
                "cpu": sum(graph.nodes[n].cpu for n in c["nodes"]),
                "memory_mib": sum(graph.nodes[n].memory_mib for n in c["nodes"]),
                "levels": sorted({levels[n] for n in c["nodes"]}, key=lambda lv: charts.LEVELS.index(lv)),
                "out_bps": sum(b["bytes_per_s"] for b in bandwidth if c["name"] in (b["a"], b["b"])),
            }
        )
    images = clustering.images
    total = clustering.inter_container_bandwidth + clustering.intra_container_bandwidth
    return render(
        request,
        "containers/clustering_detail.html",
        {
            "clustering": clustering,
            "rows": rows,
            "share_inter": clustering.inter_container_bandwidth / total * 100 if total else 0.0,
            "rosgraph_figure": to_html(charts.rosgraph_figure(graph, groups, mode), div_id="rosgraph-chart"),
            "container_figure": to_html(
                charts.container_figure(clustering.containers, bandwidth), div_id="container-chart"
            ),
            "images": images,
            "disk_figure": to_html(charts.disk_figure(images), div_id="disk-chart") if images else None,
            "saved_pct": images["saved"] * 100 if images else None,
            "archives": list(services.ARCHIVES),
            "form": form or PlaceForm(clustering=clustering, request=request),
            "placements": clustering.placements.select_related("cluster").order_by("-created", "-pk")[:20],
            "nav": NAV,
        },
        status=status,
    )


@login_required
def clustering_detail(request: HttpRequest, pk: int) -> HttpResponse:
    clustering = get_object_or_404(
        scoped(request, Clustering.objects.select_related("fleet", "rosgraph", "job")), pk=pk
    )
    return _clustering_page(request, clustering)


@login_required
def clustering_dockerfiles(request: HttpRequest, pk: int) -> HttpResponse:
    clustering = get_object_or_404(scoped(request, Clustering.objects.select_related("rosgraph")), pk=pk)
    kind = request.GET.get("archive", "tar.gz")
    if kind not in services.ARCHIVES or not clustering.images:
        raise Http404("no such archive")
    try:
        data, content_type, filename = services.dockerfiles_archive(clustering, kind)
    except InputError as exc:  # stored before names were checked: refuse to write it into a build script
        return HttpResponse(f"cannot generate the Dockerfiles: {exc}", status=409, content_type="text/plain")
    response = HttpResponse(data, content_type=content_type)
    response["Content-Disposition"] = f'attachment; filename="{filename}"'
    return response


@login_required
@require_POST
def clustering_place(request: HttpRequest, pk: int) -> HttpResponse:
    clustering = get_object_or_404(scoped(request, Clustering.objects.select_related("fleet", "rosgraph")), pk=pk)
    form = PlaceForm(request.POST, clustering=clustering, request=request)
    if not form.is_valid():
        return _clustering_page(request, clustering, form, status=400)
    job = start_job(ContainersJob.PLACE, clustering.fleet, form.job_arguments(), request.user)
    return redirect("jobs:job", pk=job.pk)


# ---- placements -------------------------------------------------------------------------------------------
@login_required
def placement_detail(request: HttpRequest, pk: int) -> HttpResponse:
    placement = get_object_or_404(
        scoped(request, Placement.objects.select_related("fleet", "cluster", "clustering", "rosgraph", "job")), pk=pk
    )
    plan = placement.engine_plan()
    order = [d.item for d in plan.decisions]
    names = [c["name"] for c in placement.containers.get("containers", [])]
    selected = request.GET.get("container") or (order[0] if order else None)
    if selected is not None and selected not in order:
        raise Http404("no such container in this placement")
    why = services.why_table(plan, selected) if selected else None
    traffic = services.node_traffic(placement)
    specs = {c["name"]: c for c in placement.containers.get("containers", [])}
    deployments = {d.container: d for d in placement.deployments.all()}
    placed = plan.placed()
    rows = [
        {
            "name": c,
            "node": placed.get(c),
            "score": decision.score if (decision := plan.decision(c)) else None,
            "spec": specs.get(c, {}),
            "deployment": deployments.get(c),
            "position": i + 1,
        }
        for i, c in enumerate(order)
    ]
    baseline = placement.baseline
    saved = None
    if baseline and baseline["inter_node_bandwidth"] > 0:
        saved = (1 - placement.inter_node_bandwidth / baseline["inter_node_bandwidth"]) * 100
    figure = charts.placement_figure(placement.cluster_document, placement.plan, traffic, names)
    can_push = bool(placement.cluster and placement.cluster.kubeconfig)
    return render(
        request,
        "containers/placement_detail.html",
        {
            "placement": placement,
            "rows": rows,
            "why": why,
            "selected": selected,
            "traffic": traffic,
            "figure": to_html(figure, div_id="placement-chart"),
            "baseline": baseline,
            "saved": saved,
            "can_push": can_push,
            "deploy_states": [
                (value, label, sum(1 for d in deployments.values() if d.state == value))
                for value, label in ContainerDeployment.State.choices
                if value != ContainerDeployment.State.NOT_PUSHED
            ],
            "nav": NAV,
        },
    )


@login_required
@require_POST
def placement_push(request: HttpRequest, pk: int) -> HttpResponse:
    placement = get_object_or_404(scoped(request, Placement.objects.select_related("fleet", "cluster")), pk=pk)
    if placement.cluster is None or not placement.cluster.kubeconfig:
        messages.error(request, "This placement's cluster has no Kubernetes API configured: nothing to push to.")
        return redirect("containers:placement", pk=placement.pk)
    if ContainersJob.PUSH_PLACEMENT not in HANDLERS:
        messages.error(request, "Pushing to Kubernetes is not available in this installation.")
        return redirect("containers:placement", pk=placement.pk)
    job = start_job(ContainersJob.PUSH_PLACEMENT, placement.fleet, {"placement": placement.pk}, request.user)
    return redirect("jobs:job", pk=job.pk)
