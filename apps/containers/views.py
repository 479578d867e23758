"""Dashboard pages of ROS graphs -> containers -> nodes. Every page needs a login and shows only the user's
fleets' objects (another fleet's answers 404)."""

from __future__ import annotations

from django.contrib import messages
from django.contrib.auth.decorators import login_required
from django.db import transaction
from django.db.models import Count
from django.http import Http404, HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, redirect, render
from django.urls import reverse
from django.views.decorators.http import require_POST

from apps.containers.kinds import ContainersJob
from apps.containers.resources import resource_model
from apps.jobs.registry import HANDLERS
from apps.jobs.services import start_job
from apps.tenancy.scoping import visible_fleets
from apps.ui.charts import to_html
from apps.ui.helpers import paginate, scoped
from continuum.engine.containers import robot_pinning
from continuum.engine.containers.resource_model import profiles as resource_profiles
from continuum.engine.containers.rosgraph import propose_levels
from continuum.engine.containers.superclustering import container_bandwidth
from continuum.engine.core.errors import InputError

from . import charts, services
from .forms import ClusterForm, LevelsForm, PlaceForm, RosGraphUploadForm, RosNodeEditForm, TopicEditForm
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


def _graph_page(
    request, row: RosGraph, *, cluster_form=None, levels_form=None, edit_form=None, status: int = 200
) -> HttpResponse:
    """``edit_form``: a bound node or topic row form that was refused, shown in its row with its errors."""
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
    levels = graph.levels()
    proposed = propose_levels(graph)
    profiles = resource_profiles(graph, resource_model())
    on_robot = robot_pinning.pinned(levels, {n: node.pin for n, node in graph.nodes.items()})

    def row_form(form_class, kind: str, item: str, initial: dict, **extra):
        if edit_form is not None and edit_form.kind == kind and edit_form.item == item:
            return edit_form
        return form_class(rosgraph=row, item=item, initial=initial, **extra)

    node_rows = [
        {
            "name": n,
            "level": levels[n],
            "given": bool(node.level),
            "pinned": n in on_robot,
            "profile": profiles[n],
            "form": row_form(
                RosNodeEditForm,
                "node",
                n,
                {"level": node.level or "", "pin": node.pin or "", "cpu": node.cpu, "memory_mib": node.memory_mib},
                proposed=proposed[n],
            ),
        }
        for n, node in sorted(graph.nodes.items())
    ]
    topic_rows = []
    for t in sorted(graph.topics.values(), key=lambda t: t.name):
        rates = sorted(set(t.rates.values()))
        # One rate for every publisher is the field's value; differing ones are shown beside an empty field.
        initial = {"rate_hz": rates[0] if len(rates) == 1 else None, "msg_bytes": t.msg_bytes}
        topic_rows.append(
            {
                "name": t.name,
                "publishers": t.publishers,
                "subscribers": t.subscribers,
                "rates": rates,
                "msg_bytes": t.msg_bytes,
                "bps": sum(t.rate(p) for p in t.publishers) * t.msg_bytes * len(t.subscribers),
                "form": row_form(TopicEditForm, "topic", t.name, initial),
            }
        )
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
            "node_rows": node_rows,
            "edit_error": edit_form,
            "topics": topic_rows,
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


def _edit(request: HttpRequest, pk: int, form_class, key: str, what: str) -> HttpResponse:
    """Save one row's edit (a ROS node or a topic) through the PATCH contract; a refused one re-renders the
    page (400) with the row's errors next to its fields and summarised at the top of its table."""
    item = request.POST.get(key, "")
    # Read, check and write under the row's lock: two rows saved at once must not undo each other.
    with transaction.atomic():
        row = get_object_or_404(scoped(request, RosGraph.objects.select_for_update(of=("self",))), pk=pk)
        graph = row.graph
        table = graph.nodes if key == "node" else graph.topics
        if item not in table:
            raise Http404(f"no {what} {item!r} in this graph")
        extra = {"proposed": propose_levels(graph)[item]} if key == "node" else {}
        form = form_class(request.POST, rosgraph=row, item=item, **extra)
        if form.is_valid():
            row.set_graph(form.graph())
            row.save()
    if not form.is_valid():
        return _graph_page(request, row, edit_form=form, status=400)
    messages.success(request, f"Saved {what} {item}.")
    return redirect(f"{reverse('containers:rosgraph', args=[row.pk])}#{key}s")


@login_required
@require_POST
def rosgraph_node(request: HttpRequest, pk: int) -> HttpResponse:
    return _edit(request, pk, RosNodeEditForm, "node", "ROS node")


@login_required
@require_POST
def rosgraph_topic(request: HttpRequest, pk: int) -> HttpResponse:
    return _edit(request, pk, TopicEditForm, "topic", "topic")


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
    profiles = resource_profiles(graph, resource_model())
    rows = []
    for c in clustering.containers:
        rows.append(
            {
                "name": c["name"],
                "nodes": c["nodes"],
                # The requests the placement uses (resource_model): work + middleware, process + queues.
                "cpu": sum(profiles[n].cpu for n in c["nodes"]),
                "memory_mib": sum(profiles[n].memory_mib for n in c["nodes"]),
                "levels": sorted({levels[n] for n in c["nodes"]}, key=lambda lv: charts.LEVELS.index(lv)),
                "out_bps": sum(b["bytes_per_s"] for b in bandwidth if c["name"] in (b["a"], b["b"])),
            }
        )
    images = clustering.images
    previews, preview_error = [], None
    if images:
        try:
            previews = services.dockerfile_previews(clustering)
        except InputError as exc:  # stored before names were checked: the archive refuses it too
            preview_error = str(exc)
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
            "dockerfiles": previews,
            "dockerfile_error": preview_error,
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
        scoped(
            request,
            # The job's arguments and result are not shown here: a placement's arguments hold its whole
            # containers document again (megabytes at thousands of containers).
            Placement.objects.select_related("fleet", "cluster", "clustering", "rosgraph", "job").defer(
                "job__arguments",
                "job__result",
                "clustering__graph_document",
                "clustering__result",
                "clustering__images",
                "rosgraph__document",
            ),
        ),
        pk=pk,
    )
    # The stored plan read as it is: only the selected container's decision becomes engine objects (a plan
    # of 5,000 containers has tens of thousands of verdicts; building them all took seconds).
    decisions = placement.plan.get("decisions") or []
    order = [d["item"] for d in decisions]
    names = [c["name"] for c in placement.containers.get("containers", [])]
    selected = request.GET.get("container") or (order[0] if order else None)
    if selected is not None and selected not in order:
        raise Http404("no such container in this placement")
    full = request.GET.get("full") == "1"
    why = services.why_table(placement.plan, selected, placement, full=full) if selected else None
    traffic = services.node_traffic(placement)
    specs = {c["name"]: c for c in placement.containers.get("containers", [])}
    deployments = {d.container: d for d in placement.deployments.all()}
    by_item = {d["item"]: d for d in decisions}
    rows = [
        {
            "name": c,
            "node": by_item[c].get("node"),
            "score": by_item[c].get("score"),
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
    warnings = services.placement_warnings(placement)
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
            "warnings": warnings,
            "off_robot": {w["container"] for w in warnings},
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
