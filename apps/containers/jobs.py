"""Job handlers: ``cluster_ros`` (Listing 3.20 + images), ``place`` (Fig. 3.27) and ``push_placement``.

Each handler is idempotent: a re-delivered job replaces what an earlier attempt of the same job stored.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from django.conf import settings
from django.db import transaction
from django.urls import reverse

from apps.clusters.models import Cluster
from apps.containers.kinds import ContainersJob
from apps.jobs.registry import job_kind, owned_row
from continuum.engine.containers.image_inheritance import dependency_sets
from continuum.engine.containers.ros_clustering import cluster_ros as engine_cluster_ros
from continuum.engine.containers.ros_clustering import max_containers
from continuum.engine.containers.superclustering import FULL_UP_TO, bounded_plan
from continuum.engine.containers.superclustering import place as engine_place
from continuum.engine.core.errors import InputError

from . import imagebuild, services
from .models import Clustering, Placement, RosGraph
from .resources import clustering_method

BASELINES = {"superclustering": "default-kubernetes", "default-kubernetes": "superclustering"}


def container_count(arguments: dict) -> int:
    """N as asked, or the Eq. 3.13 bound from the memory and the per-container overhead."""
    n = arguments.get("containers")
    memory, overhead = arguments.get("memory_mib"), arguments.get("overhead_mib")
    if n is None:
        if memory is None or overhead is None:
            raise InputError("give the number of containers, or memory_mib and overhead_mib (Eq. 3.13)", "containers")
        return max_containers(memory, overhead)
    return n


@job_kind(ContainersJob.CLUSTER_ROS)
def cluster_job(job, progress) -> tuple[dict, str]:
    """Arguments: ``rosgraph`` (id); ``containers`` (N) or ``memory_mib`` + ``overhead_mib``; ``mode``,
    ``max_cluster_share``, ``max_cluster_memory_mib``; ``images`` (plan options)."""
    args = job.arguments or {}
    rosgraph = owned_row(job, RosGraph.objects, "rosgraph", what="ROS graph")
    progress(2, f"reading {rosgraph.name}")
    graph = rosgraph.graph
    n = container_count(args)
    progress(10, f"clustering {len(graph.nodes)} ROS nodes into {n} containers")
    result = engine_cluster_ros(
        graph,
        n,
        mode=args.get("mode") or "per_topic",
        available_mib=args.get("memory_mib"),
        overhead_mib=args.get("overhead_mib"),
        max_cluster_share=args.get("max_cluster_share"),
        max_cluster_memory_mib=args.get("max_cluster_memory_mib"),
        method=clustering_method(),
    )
    groups = {c.name: list(c.nodes) for c in result.containers}
    images = None
    options = services.image_options(args.get("images"))
    if services.has_packages(graph):
        progress(60, f"planning the images of {len(groups)} containers")
        images = services.stored_images(services.image_plan(graph, groups, options))
    progress(90, "storing the clustering")
    params = {
        key: args.get(key)
        for key in ("containers", "memory_mib", "overhead_mib", "mode", "max_cluster_share", "max_cluster_memory_mib")
        if args.get(key) is not None
    }
    params["images"] = options
    params["method"] = result.params["method"]
    with transaction.atomic():
        Clustering.objects.filter(job=job).delete()
        row = Clustering.objects.create(
            fleet=rosgraph.fleet,
            rosgraph=rosgraph,
            job=job,
            requested_containers=n,
            container_count=len(result.containers),
            params=params,
            graph_document=graph.to_dict(),
            result=result.to_dict(),
            inter_container_bandwidth=result.inter_container_bandwidth,
            intra_container_bandwidth=result.intra_container_bandwidth,
            images=images,
            disk_before_mib=images["before_mib"] if images else None,
            disk_after_mib=images["after_mib"] if images else None,
        )
    summary = {
        "clustering": row.pk,
        "containers": row.container_count,
        "inter_container_bandwidth": row.inter_container_bandwidth,
        "intra_container_bandwidth": row.intra_container_bandwidth,
        "guard_fired": result.guard_fired,
        "page": reverse("containers:clustering", args=[row.pk]),
    }
    if images:
        summary["disk"] = {"before_mib": images["before_mib"], "after_mib": images["after_mib"]}
    return summary, f"/api/v1/clusterings/{row.pk}/"


def placement_params(args: dict) -> dict[str, Any]:
    params: dict[str, Any] = {
        "overhead_mib": float(args.get("overhead_mib") or 0.0),
        "seed": int(args.get("seed") or 0),
    }
    if args.get("weights"):
        params["weights"] = dict(args["weights"])
    # The robot constraint (robot_pinning): the request's choice, else the settings' defaults.
    params["drivers_on_robot"] = bool(args.get("drivers_on_robot", settings.CONTINUUM_DRIVERS_ON_ROBOT))
    params["robot_label"] = args.get("robot_label") or settings.CONTINUUM_ROBOT_LABEL
    return params


@job_kind(ContainersJob.PLACE)
def place_job(job, progress) -> tuple[dict, str]:
    """Arguments: ``cluster`` (id), ``policy``; ``clustering`` (id, with optional ``overrides`` and
    ``archs``) or ``containers`` (a continuum.containers/v1 document, with an optional ``rosgraph`` id for
    Definition 3.2.1 bandwidth); ``weights``, ``seed``, ``overhead_mib``; ``compare`` (default true);
    ``drivers_on_robot``, ``robot_label`` (defaults: the settings). Off-robot drivers are in ``warnings``."""
    args = job.arguments or {}
    cluster = owned_row(job, Cluster.objects, "cluster")
    clustering = rosgraph = None
    progress(2, "reading the containers")
    if args.get("clustering") is not None:
        clustering = owned_row(job, Clustering.objects, "clustering")
        rosgraph = clustering.rosgraph
        workload, resolved = services.clustering_workload(
            clustering, archs=args.get("archs"), overrides=args.get("overrides")
        )
    else:
        if not isinstance(args.get("containers"), dict):
            raise ValueError("give a clustering id or a continuum.containers/v1 document")
        rosgraph = owned_row(job, RosGraph.objects, "rosgraph", what="ROS graph", required=False)
        workload, resolved = services.resolve_workload(args["containers"], rosgraph.graph if rosgraph else None)
    engine = services.engine_cluster(cluster)
    policy = args.get("policy") or "superclustering"
    params = placement_params(args)
    progress(20, f"placing {len(workload.containers)} containers on {len(engine.nodes)} nodes ({policy})")
    plan = engine_place(policy, workload, engine, **params)
    baseline = None
    if args.get("compare", True):
        other = BASELINES[plan.policy]
        progress(60, f"placing them again with {other} for comparison")
        alt_params = {k: v for k, v in params.items() if k != "weights"}
        alt = engine_place(other, workload, engine, **alt_params)
        baseline = {
            "policy": other,
            "inter_node_bandwidth": alt.metrics["inter_node_bandwidth"],
            # Only where things went: ``alt.to_dict()`` would build every node's verdict for every container.
            "placements": [{"container": d.item, "node": d.node, "score": d.score} for d in alt.decisions if d.node],
            "pending": [d.item for d in alt.decisions if d.pending],
        }
    progress(90, "storing the placement")
    # On more than FULL_UP_TO nodes, bounded explanations (the best candidates, the count of nodes per filter,
    # an example each): every node's verdict for every container was hundreds of MiB at 5,000 x 500, over
    # jsonb's limit. The rest is recomputed from the stored inputs when asked (why_table(..., full=True)).
    doc = (bounded_plan(plan) if len(engine.nodes) > FULL_UP_TO else plan).to_dict()
    with transaction.atomic():
        Placement.objects.filter(job=job).delete()
        row = Placement.objects.create(
            fleet=cluster.fleet,
            clustering=clustering,
            rosgraph=rosgraph,
            cluster=cluster,
            job=job,
            policy=plan.policy,
            params=plan.params,
            containers=resolved,
            cluster_document=engine.to_dict(),
            plan=doc,
            inter_node_bandwidth=plan.metrics["inter_node_bandwidth"],
            placed_count=len(doc["placements"]),
            pending_count=len(doc["pending"]),
            baseline=baseline,
        )
    summary = {
        "placement": row.pk,
        "policy": row.policy,
        "placed": row.placed_count,
        "pending": row.pending_count,
        "inter_node_bandwidth": row.inter_node_bandwidth,
        "page": reverse("containers:placement", args=[row.pk]),
    }
    if baseline:
        summary["baseline"] = {"policy": baseline["policy"], "inter_node_bandwidth": baseline["inter_node_bandwidth"]}
    warnings = services.placement_warnings(row)
    if warnings:
        summary["warnings"] = [w["message"] for w in warnings]
    return summary, f"/api/v1/placements/{row.pk}/"


@job_kind(ContainersJob.PUSH_PLACEMENT)
def push_job(job, progress) -> tuple[dict, str]:
    """Arguments: ``placement`` (id). One Deployment per container, pinned to its node (see ``kube.py``)."""
    from .kube import push_placement

    placement = owned_row(job, Placement.objects, "placement")
    progress(1, f"pushing placement {placement.pk} to {placement.cluster or 'no cluster'}")
    summary = push_placement(placement, progress)
    summary["page"] = reverse("containers:placement", args=[placement.pk])
    return summary, f"/api/v1/placements/{placement.pk}/"


@job_kind(ContainersJob.BUILD_IMAGES)
def build_images_job(job, progress) -> tuple[dict, str]:
    """Arguments: ``clustering`` (id); ``export`` (default false: also write each container image as a
    docker-archive under ``CONTINUUM_CACHE``/images/built for ``scripts/cluster import-image``). The clustering's
    containers' packages must be Debian names (see :mod:`continuum.engine.containers.debian_images`). Builds
    with buildah on the worker's machine (root), measures every layer, stores it in the clustering's ``images``
    under ``built`` (with the planner's prediction from apt's metadata and the thesis' 83.2 %)."""
    args = job.arguments or {}
    clustering = owned_row(job, Clustering.objects, "clustering", what="clustering")
    deps = dependency_sets(clustering.graph, clustering.groups())
    deps = {c: pkgs for c, pkgs in deps.items() if pkgs}
    if not deps:
        raise InputError("the clustering's ROS nodes list no packages: nothing to build", "clustering")
    progress(2, f"predicting the sizes of {len(deps)} container images from apt's metadata")
    try:
        plan, _ = imagebuild.predict(deps)
        built = imagebuild.build(plan, progress)
        if args.get("export"):
            where = Path(os.environ.get("CONTINUUM_CACHE") or Path.home() / ".cache" / "continuum") / "images" / "built"
            for im in built["images"]:
                progress(95, f"exporting {im['reference']}")
                im["archive"] = str(imagebuild.export(im["reference"], where))
    except imagebuild.BuildError as exc:
        raise InputError(str(exc), "images") from exc
    with transaction.atomic():
        row = Clustering.objects.select_for_update().get(pk=clustering.pk)
        row.images = {**(row.images or {}), "built": built}
        row.save(update_fields=["images"])
    keys = ("before_mib", "after_mib", "saved", "predicted_saved", "thesis_saved")
    summary = {"clustering": row.pk, "images": len(built["images"]), **{k: built[k] for k in keys},
               "page": reverse("containers:clustering", args=[row.pk])}  # fmt: skip
    return summary, summary["page"]
