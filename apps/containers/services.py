"""Glue between the stored objects and the engine: graph import and edits, clusters as engine clusters, the
workload of a clustering, the "why" table of a placement, the Dockerfiles archive.

Every check that can fail raises :class:`~continuum.engine.core.errors.InputError` naming the culprit (the API turns
it into a 400 under the error's field).
"""

from __future__ import annotations

import copy
import gzip
from collections.abc import Mapping
from typing import Any

from apps.clusters.models import Cluster
from apps.containers.resources import resource_model
from continuum.engine.containers.image_inheritance import DEFAULT_PLATFORMS, ImagePlan, plan_from_graph
from continuum.engine.containers.rosgraph import (
    LEVEL_ALIASES,
    LEVELS,
    RosGraph,
    guess_json_format,
    load_rosgraph,
    natural_key,
    pair,
)
from continuum.engine.containers.superclustering import (
    CONTAINERS_FORMAT,
    SCORERS,
    Workload,
    decision_verdicts,
    load_workload,
)
from continuum.engine.core import artifact_names
from continuum.engine.core.cluster import Cluster as EngineCluster
from continuum.engine.core.errors import InputError
from continuum.engine.core.placement import Decision, PlacementPlan
from continuum.engine.core.safeload import loads_json

from .models import Clustering, Placement

#: Image options of a clustering (``plan_from_graph`` keywords) and their defaults.
IMAGE_DEFAULTS: dict[str, Any] = {
    "distro_image": "ros:humble-ros-base",
    "ros_distro": "humble",
    "distro_mib": 0.0,
    "platforms": list(DEFAULT_PLATFORMS),
    "repository": "continuum",
    "tag": "latest",
}
#: What a placement request may change about one container of a clustering (continuum.containers/v1 keys).
OVERRIDE_KEYS = (
    "cpu", "memory_mib", "storage_mib", "priority", "archs", "node", "node_selector", "affinity", "tolerations",
    "image",
)  # fmt: skip
ARCHIVES = {
    "tar.gz": ("application/gzip", "tar.gz"),
    "zip": ("application/zip", "zip"),
}


# ---- import -------------------------------------------------------------------------------------------
def read_graph(content: bytes | str, fmt: str | None = None, name: str = "") -> tuple[RosGraph, str]:
    """Parse an uploaded ROS graph; returns the graph and the format it was read as."""
    if isinstance(content, bytes):
        try:
            content = content.decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            raise InputError(f"not UTF-8 text (byte {exc.start})") from exc
    graph = load_rosgraph(content, fmt, name=name)
    if fmt:
        return graph, fmt
    if not content.lstrip().startswith(("{", "[")):
        return graph, "dot"
    return graph, guess_json_format(loads_json(content))


# ---- edits --------------------------------------------------------------------------------------------
_RATE_KEYS = ("rate_hz", "period_ms", "publisher_rates_hz", "messages", "window_s")
_TOPIC_EDIT_KEYS = {"rate_hz", "period_ms", "publisher_rates_hz", "msg_bytes", "msg_type"}
_NODE_EDIT_KEYS = {"level", "context", "origin", "cpu", "memory_mib", "packages", "pin"}


def normal_level(raw: Any, where: str) -> str | None:
    """A Fig. 3.19 level (aliases accepted), or ``None`` to let the graph's structure propose one."""
    if raw is None or raw == "":
        return None
    level = LEVEL_ALIASES.get(str(raw).lower(), str(raw).lower()) if isinstance(raw, str) else None
    if level not in LEVELS:
        raise InputError(f"{where}: unknown level {raw!r} (one of {', '.join(LEVELS)})", "levels")
    return level


def edit_graph(
    document: Mapping[str, Any],
    *,
    levels: Mapping[str, Any] | None = None,
    topics: Mapping[str, Any] | None = None,
    nodes: Mapping[str, Any] | None = None,
    packages: Mapping[str, Any] | None = None,
) -> RosGraph:
    """The graph with levels, topic rates and message sizes, node profiles and package sizes changed.

    ``levels``: ROS node -> level (``null`` = proposed from the structure). ``topics``: topic -> any of
    ``rate_hz``/``period_ms``/``publisher_rates_hz`` (replaces the rate), ``msg_bytes``, ``msg_type``.
    ``nodes``: ROS node -> any of ``level``, ``context``, ``origin``, ``cpu``, ``memory_mib``, ``packages``.
    ``packages``: package -> size in MiB, ``{size_mib, archs, apt}``, or ``null`` to forget it.
    """
    doc = copy.deepcopy(dict(document))
    by_node = {n["name"]: n for n in doc.get("nodes", [])}
    by_topic = {t["name"]: t for t in doc.get("topics", [])}
    for name, changes in (nodes or {}).items():
        if name not in by_node:
            raise InputError(f"unknown ROS node {name!r}", "nodes")
        if not isinstance(changes, Mapping):
            raise InputError(f"ROS node {name!r}: changes must be an object", "nodes")
        unknown = sorted(set(changes) - _NODE_EDIT_KEYS)
        if unknown:
            raise InputError(f"ROS node {name!r}: cannot change {unknown[0]!r}", "nodes")
        for key, value in changes.items():
            if key == "level":
                value = normal_level(value, f"ROS node {name!r}")
            _set_or_drop(by_node[name], key, value)
    for name, level in (levels or {}).items():
        if name not in by_node:
            raise InputError(f"unknown ROS node {name!r}", "levels")
        _set_or_drop(by_node[name], "level", normal_level(level, f"ROS node {name!r}"))
    rates_changed = False
    for name, changes in (topics or {}).items():
        if name not in by_topic:
            raise InputError(f"unknown topic {name!r}", "topics")
        if not isinstance(changes, Mapping):
            raise InputError(f"topic {name!r}: changes must be an object", "topics")
        unknown = sorted(set(changes) - _TOPIC_EDIT_KEYS)
        if unknown:
            raise InputError(f"topic {name!r}: cannot change {unknown[0]!r}", "topics")
        given = [k for k in _RATE_KEYS if k in changes]
        if len(given) > 1:
            raise InputError(f"topic {name!r}: give one of rate_hz, period_ms, publisher_rates_hz", "topics")
        topic = by_topic[name]
        if given:
            rates_changed = True
            for key in _RATE_KEYS:
                topic.pop(key, None)
        topic.update(changes)
    if packages:
        table = dict(doc.get("packages") or {})
        for name, value in packages.items():
            if value is None:
                table.pop(name, None)
            else:
                table[name] = value
        doc["packages"] = table
    if rates_changed and isinstance(doc.get("meta"), dict):
        doc["meta"].pop("topic_rates_hz", None)  # the importer's rates no longer hold
    return RosGraph.from_dict(doc)


def _set_or_drop(item: dict, key: str, value: Any) -> None:
    if value is None:
        item.pop(key, None)
    else:
        item[key] = value


# ---- clusters -----------------------------------------------------------------------------------------
def engine_cluster(cluster: Cluster) -> EngineCluster:
    """The cluster's nodes and links as the node-level placers see them: :meth:`Cluster.to_engine`, whose nodes
    that are not Ready carry the taint Kubernetes would give them, so the placement rejects them with that
    reason instead of silently dropping them."""
    return cluster.to_engine()


# ---- images -------------------------------------------------------------------------------------------
def image_options(raw: Mapping[str, Any] | None) -> dict[str, Any]:
    options = {**IMAGE_DEFAULTS, **(raw or {})}
    unknown = sorted(set(options) - set(IMAGE_DEFAULTS))
    if unknown:
        raise InputError(f"unknown image option {unknown[0]!r} (one of {', '.join(IMAGE_DEFAULTS)})", "images")
    # Job arguments are checked by the API's serializer; a job stored otherwise meets the same grammar here.
    if options["repository"]:
        artifact_names.check_repository(options["repository"], "images", "images.repository")
    artifact_names.check_tag(options["tag"], "images", "images.tag")
    artifact_names.check_reference(options["distro_image"], "images", "images.distro_image")
    artifact_names.check_ros_distro(options["ros_distro"], "images", "images.ros_distro")
    return options


def has_packages(graph: RosGraph) -> bool:
    return any(node.packages for node in graph.nodes.values())


def image_plan(graph: RosGraph, groups: Mapping[str, list[str]], options: Mapping[str, Any]) -> ImagePlan:
    opts = image_options(options)
    return plan_from_graph(graph, groups, **opts)


def stored_images(plan: ImagePlan) -> dict[str, Any]:
    """``ImagePlan.to_dict()`` plus what pushing needs: each container's image reference."""
    return {
        **plan.to_dict(),
        "repository": plan.repository,
        "tag": plan.tag,
        "references": {c: plan.reference(im.name) for c, im in plan.container_images().items()},
    }


def dockerfiles_archive(clustering: Clustering, kind: str) -> tuple[bytes, str, str]:
    """(bytes, content type, file name) of the clustering's Dockerfiles, ``build.sh`` and ``plan.json``.

    The plan is computed again from the stored graph snapshot and options (deterministic), so the archive
    always matches the stored figures; the gzip header carries no time stamp, so the same plan gives the
    same bytes.
    """
    if kind not in ARCHIVES:
        raise InputError(f"unknown archive {kind!r} (one of {', '.join(ARCHIVES)})", "archive")
    plan = stored_plan(clustering)
    data = plan.archive("zip") if kind == "zip" else gzip.compress(plan.archive("tar"), mtime=0)
    content_type, suffix = ARCHIVES[kind]
    return data, content_type, f"{_file_stem(clustering)}-dockerfiles.{suffix}"


def stored_plan(clustering: Clustering) -> ImagePlan:
    """The clustering's image plan computed again from its graph snapshot and options: the one generator of
    the Dockerfiles that the archive (API, page) and the page's preview show."""
    if not clustering.images:
        raise InputError("this clustering has no image plan: its ROS nodes list no packages", "archive")
    return image_plan(clustering.graph, clustering.groups(), clustering.params.get("images") or {})


def dockerfile_previews(clustering: Clustering) -> list[dict[str, Any]]:
    """Each image's Dockerfile as the archive holds it (``<image>/Dockerfile``), parents first, with the
    containers built from it; an error string instead when the stored names no longer pass their grammar."""
    plan = stored_plan(clustering)
    return [
        {"image": im.name, "kind": im.kind, "owners": list(im.owners), "reference": plan.reference(im.name),
         "dockerfile": plan.dockerfiles[im.name]}
        for im in plan.images
    ]  # fmt: skip


def _file_stem(clustering: Clustering) -> str:
    from apps.kube.gateway import dns_part

    return f"{dns_part(clustering.rosgraph.name, 40)}-{clustering.pk}"


# ---- workloads ----------------------------------------------------------------------------------------
def clustering_workload(
    clustering: Clustering,
    *,
    archs: list[str] | None = None,
    overrides: Mapping[str, Mapping[str, Any]] | None = None,
) -> tuple[Workload, dict[str, Any]]:
    """The containers of a clustering as a workload: images' platforms as archs, CPU and memory summed over
    the ROS nodes, bandwidth by Definition 3.2.1; ``overrides`` change single containers. Returns the
    workload and its resolved ``continuum.containers/v1`` document (with each container's ``image``)."""
    refs = (clustering.images or {}).get("references", {})
    platforms = {
        im["owners"][0]: im["platforms"]
        for im in (clustering.images or {}).get("images", [])
        if im["kind"] == "container"
    }
    overrides = dict(overrides or {})
    names = {c["name"] for c in clustering.containers}
    for name, changes in overrides.items():
        if name not in names:
            raise InputError(f"unknown container {name!r}", "overrides")
        if not isinstance(changes, Mapping):
            raise InputError(f"container {name!r}: changes must be an object", "overrides")
        unknown = sorted(set(changes) - set(OVERRIDE_KEYS))
        if unknown:
            raise InputError(
                f"container {name!r}: cannot change {unknown[0]!r} (one of {', '.join(OVERRIDE_KEYS)})", "overrides"
            )
    entries = []
    for c in clustering.containers:
        entry: dict[str, Any] = {"name": c["name"], "nodes": list(c["nodes"])}
        if c["name"] in platforms:
            entry["archs"] = platforms[c["name"]]
        if c["name"] in refs:
            entry["image"] = refs[c["name"]]
        entry.update(overrides.get(c["name"], {}))
        entries.append(entry)
    doc: dict[str, Any] = {"format": CONTAINERS_FORMAT, "containers": entries}
    if archs:
        doc["archs"] = archs
    return resolve_workload(doc, clustering.graph)


def resolve_workload(doc: Mapping[str, Any], graph: RosGraph | None = None) -> tuple[Workload, dict[str, Any]]:
    """Read a containers document (with the graph for Definition 3.2.1 bandwidth) and resolve it."""
    workload = load_workload(doc, graph, resource_model())
    resolved = workload.to_dict()
    images = {c.get("name"): c.get("image") for c in doc.get("containers", []) if isinstance(c, Mapping)}
    for entry in resolved["containers"]:
        image = images.get(entry["name"])
        if image is not None:
            problem = artifact_names.reference_problem(image.strip() if isinstance(image, str) else image)
            if problem is not None:
                raise InputError(f"container {entry['name']!r}: 'image' must be an image reference: {problem}",
                                 "containers")  # fmt: skip
            entry["image"] = image.strip()
    return workload, resolved


# ---- read-outs ----------------------------------------------------------------------------------------
def why_table(
    plan: PlacementPlan | Mapping[str, Any], container: str, placement: Placement | None = None, full: bool = False
) -> dict[str, Any]:
    """Why ``container`` went where it went: for every node, the filter that rejected it and the reason, or
    what each scoring policy gave it and the total (the chosen node first, then by total, rejected last).
    ``plan`` is the engine's plan or its stored form (``PlacementPlan.to_dict()``). A stored plan keeps a
    bounded explanation (``rejections``: nodes per filter; the best candidates and an example per filter in
    ``rows``); with ``full`` and the ``placement``, every node's verdict is recomputed from its stored inputs."""
    if isinstance(plan, PlacementPlan):
        order = [d.item for d in plan.decisions]
        if container not in order:
            raise KeyError(container)
        decision = plan.decisions[order.index(container)]
        policy = plan.policy
    else:  # the stored form: only this container's decision is read back
        order = [d.get("item") for d in plan.get("decisions") or []]
        if container not in order:
            raise KeyError(container)
        decision = Decision.from_dict(plan["decisions"][order.index(container)])
        policy = plan.get("policy", "")
    if full and decision.rejections and placement is not None:
        decision = full_decision(placement, container)
    # A fixed order: JSON stored in PostgreSQL (jsonb) does not keep the order of a plan's keys.
    used = {p for v in decision.verdicts for p in v.scores}
    policies = sorted(used, key=lambda p: (SCORERS.index(p) if p in SCORERS else len(SCORERS), p))
    rows = []
    for v in decision.verdicts:
        chosen = v.node == decision.node
        rows.append(
            {
                "node": v.node,
                "verdict": "chosen" if chosen else ("rejected" if v.rejected_by else "feasible"),
                "rejected_by": v.rejected_by,
                "reason": v.reason,
                "scores": dict(v.scores),
                "total": v.total,
            }
        )
    rank = {"chosen": 0, "feasible": 1, "rejected": 2}
    rows.sort(key=lambda r: (rank[r["verdict"]], -(r["total"] or 0.0) if r["verdict"] != "rejected" else 0))
    return {
        "container": container,
        "position": order.index(container) + 1,
        "node": decision.node,
        "score": decision.score,
        "pending": decision.pending,
        "policy": policy,
        "policies": policies,
        "rows": rows,
        # Bounded: ``rows`` are a sample and these are the counts of rejected nodes per filter.
        "rejections": dict(decision.rejections),
        "bounded": bool(decision.rejections),
    }


#: Parameters of a stored plan that ``place()`` takes back (the rest, e.g. ``tie_break``, follow from the policy).
_REPLAY = ("weights", "overhead_mib", "drivers_on_robot", "robot_label", "seed")


def full_decision(placement: Placement, container: str) -> Decision:
    """Every node's verdict on ``container``, recomputed from the placement's stored inputs (its resolved
    containers, its cluster snapshot and parameters): the run is deterministic, so the same decision."""
    params = {k: v for k, v in (placement.params or {}).items() if k in _REPLAY}
    return decision_verdicts(placement.policy, placement.workload(), placement.engine_cluster(), container, **params)


def node_traffic(placement: Placement) -> list[dict[str, Any]]:
    """Bytes/s between each pair of nodes that exchange data under the placement."""
    placed = placement.placed()
    totals: dict[tuple[str, str], float] = {}
    for item in placement.containers.get("bandwidth", []):
        na, nb = placed.get(item["a"]), placed.get(item["b"])
        if na is None or nb is None or na == nb or not item["bytes_per_s"]:
            continue
        key = pair(na, nb)
        totals[key] = totals.get(key, 0.0) + item["bytes_per_s"]
    return [
        {"a": a, "b": b, "bytes_per_s": w}
        for (a, b), w in sorted(totals.items(), key=lambda kv: (natural_key(kv[0][0]), natural_key(kv[0][1])))
    ]


def placement_warnings(placement: Placement) -> list[dict[str, Any]]:
    """Driver-level ROS nodes the placement put off the robot (the plan's ``off_robot_drivers`` metric,
    :func:`continuum.engine.containers.robot_pinning.off_robot`), with a message each."""
    plan = placement.plan or {}  # PlacementPlan.to_dict() writes the metrics at the top level
    out = [dict(w) for w in plan.get("off_robot_drivers") or [] if isinstance(w, Mapping)]
    if out and not plan.get("robot_nodes"):
        label = (placement.params or {}).get("robot_label", "zone=robot")
        for w in out:
            w["message"] += f"; the cluster has no node labelled {label}"
    return out
