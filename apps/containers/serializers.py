from __future__ import annotations

from django.conf import settings
from rest_framework import serializers

from apps.clusters.serializers import VisibleClusterField
from apps.tenancy.api import (
    ChosenFleetMixin,
    DefaultFleetMixin,
    FleetField,
    ScopedModelSerializer,
    ScopedSerializer,
    VisibleRelatedField,
)
from apps.tenancy.bounds import BoundedFileField, at_most
from continuum.engine.containers.robot_pinning import parse_label
from continuum.engine.containers.ros_clustering import max_containers
from continuum.engine.containers.rosgraph import LEVELS, MODES, PINS, READERS
from continuum.engine.containers.superclustering import ALIASES, POLICIES, SCORERS
from continuum.engine.core import artifact_names, limits
from continuum.engine.core.cluster import normalize_arch
from continuum.engine.core.errors import InputError

from . import services
from .models import Clustering, ContainerDeployment, Placement, RosGraph


def input_error(exc: InputError, default: str) -> serializers.ValidationError:
    return serializers.ValidationError({exc.field or default: [str(exc)]})


# ---- ROS graphs -------------------------------------------------------------------------------------------
def _bounded(name: str, unit: str, maximum: float, **kwargs) -> serializers.FloatField:
    """A non-negative number bounded by the limit; messages and help text carry the unit."""
    shown = f"{int(maximum):,}" if float(maximum).is_integer() else f"{maximum:g}"
    return serializers.FloatField(
        min_value=0,
        max_value=maximum,
        required=False,
        error_messages={
            "max_value": f"{name}: at most {shown} {unit}",
            "min_value": f"{name}: must be at least 0 {unit}",
        },
        help_text=f"{unit}, 0 to {shown}",
        **kwargs,
    )


class _StrictSerializer(ScopedSerializer):
    """Refuses keys it does not know (a plain Serializer drops them silently: a typo would be a no-op)."""

    def to_internal_value(self, data):
        if isinstance(data, dict):
            unknown = sorted(set(data) - set(self.fields))
            if unknown:
                raise serializers.ValidationError(
                    {unknown[0]: [f"cannot change {unknown[0]!r} (one of {', '.join(self.fields)})"]}
                )
        return super().to_internal_value(data)


class RosNodeEditSerializer(_StrictSerializer):
    """What PATCH (and the ROS graph page's node rows) may change about one ROS node. ``null`` level: the level
    proposed from the graph's structure; ``null`` pin: the level decides (drivers stay on the robot)."""

    level = serializers.CharField(
        required=False, allow_null=True, allow_blank=True, max_length=40,
        help_text=f"Fig. 3.19 level: {', '.join(LEVELS)} (null: proposed from the structure)",
    )  # fmt: skip
    context = serializers.CharField(required=False, allow_blank=True, max_length=200)
    origin = serializers.CharField(required=False, allow_blank=True, max_length=64)
    cpu = _bounded("cpu", "cores", limits.get().cores, allow_null=True)
    memory_mib = _bounded("memory_mib", "MiB", limits.get().memory_mib, allow_null=True)
    packages = serializers.ListField(child=serializers.CharField(max_length=214), required=False, max_length=1000)
    pin = serializers.ChoiceField(
        choices=PINS, required=False, allow_null=True, allow_blank=True,
        help_text="robot: keep on the robot's boards; free: the placement may move it; null: drivers stay on the robot",
    )  # fmt: skip

    def validate(self, attrs):
        # "" means "not set" in a form; the engine's documents use null.
        return {k: (None if v == "" and k in ("level", "pin") else v) for k, v in attrs.items()}


class TopicEditSerializer(_StrictSerializer):
    """What PATCH (and the ROS graph page's topic rows) may change about one topic: one of the rate forms
    (replaces the rate of every publisher), the message size and type."""

    rate_hz = _bounded("rate_hz", "Hz", limits.get().rate_hz)
    period_ms = serializers.FloatField(
        min_value=1000 / limits.get().rate_hz,  # the rate limit, as a period
        max_value=86_400_000,
        required=False,
        help_text="ms between messages (instead of rate_hz)",
    )
    publisher_rates_hz = serializers.DictField(
        child=serializers.FloatField(min_value=0, max_value=limits.get().rate_hz, error_messages=at_most("rate_hz")),
        required=False,
        help_text="publisher -> Hz",
    )
    msg_bytes = _bounded("msg_bytes", "bytes", limits.get().msg_bytes)
    msg_type = serializers.CharField(required=False, allow_blank=True, max_length=200)


class RosGraphEditSerializer(ScopedSerializer):
    """One edit of a ROS graph (context ``rosgraph``): the request contract of PATCH and of the page's forms."""

    levels = serializers.DictField(
        child=serializers.CharField(allow_null=True, allow_blank=True),
        required=False,
        help_text="ROS node -> level (null: proposed)",
    )
    topics = serializers.DictField(child=TopicEditSerializer(), required=False, help_text="topic -> changes")
    nodes = serializers.DictField(child=RosNodeEditSerializer(), required=False, help_text="ROS node -> changes")
    packages = serializers.DictField(required=False, help_text="package -> size_mib or object")

    def validate(self, attrs):
        edits = {key: attrs[key] for key in ("levels", "topics", "nodes", "packages") if key in attrs}
        if edits:
            try:
                attrs["graph"] = services.edit_graph(self.context["rosgraph"].document, **edits)
            except InputError as exc:
                raise input_error(exc, "document") from exc
        return attrs


class RosGraphSerializer(ScopedModelSerializer):
    """A ROS graph; PATCH edits levels, topic rates and message sizes, node profiles and package sizes.

    ``levels``: ``{ros node: level or null}``; ``topics``: ``{topic: {rate_hz | period_ms |
    publisher_rates_hz, msg_bytes, msg_type}}``; ``nodes``: ``{ros node: {level, context, origin, cpu,
    memory_mib, packages}}``; ``packages``: ``{package: size_mib | {size_mib, archs, apt} | null}``.
    """

    fleet = serializers.SlugRelatedField(slug_field="slug", read_only=True)
    levels = serializers.DictField(
        child=serializers.CharField(allow_null=True, allow_blank=True),
        required=False,
        write_only=True,
        help_text="ROS node -> level (null: proposed)",
    )
    topics = serializers.DictField(
        child=TopicEditSerializer(), required=False, write_only=True, help_text="topic -> {rate_hz, msg_bytes, ...}"
    )
    nodes = serializers.DictField(
        child=RosNodeEditSerializer(), required=False, write_only=True, help_text="ROS node -> {cpu, pin, ...}"
    )
    packages = serializers.DictField(required=False, write_only=True, help_text="package -> size_mib or object")
    effective_levels = serializers.SerializerMethodField(help_text="each ROS node's level, given or proposed")

    class Meta:
        model = RosGraph
        fields = [
            "id",
            "fleet",
            "name",
            "description",
            "source_format",
            "node_count",
            "topic_count",
            "document",
            "effective_levels",
            "levels",
            "topics",
            "nodes",
            "packages",
            "created",
            "updated",
        ]
        read_only_fields = ["source_format", "node_count", "topic_count", "document", "created", "updated"]

    def get_effective_levels(self, obj) -> dict[str, str]:
        return obj.graph.levels()

    def validate(self, attrs):
        attrs = super().validate(attrs)
        edits = {key: attrs.pop(key) for key in ("levels", "topics", "nodes", "packages") if key in attrs}
        if edits:
            edit = RosGraphEditSerializer(context={"rosgraph": self.instance})
            attrs["graph"] = edit.validate(edits)["graph"]
        return attrs

    def update(self, instance, validated):
        graph = validated.pop("graph", None)
        if graph is not None:
            instance.set_graph(graph)
        return super().update(instance, validated)


class RosGraphListSerializer(RosGraphSerializer):
    class Meta(RosGraphSerializer.Meta):
        fields = ["id", "fleet", "name", "description", "source_format", "node_count", "topic_count", "created"]


class RosGraphImportSerializer(DefaultFleetMixin, ChosenFleetMixin, ScopedSerializer):
    """Upload a ROS graph: continuum.rosgraph/v1, Autoware reference system JSON, iRobot ros2-performance
    topology JSON or an rqt_graph ``.dot``. A bad file is refused whole with the line or element at fault."""

    fleet = FleetField(required=False)
    file = BoundedFileField()
    format = serializers.ChoiceField(choices=READERS, required=False, help_text="default: guessed from the file")
    name = serializers.CharField(max_length=200, required=False, help_text="default: the name in the file")
    description = serializers.CharField(required=False, allow_blank=True, default="")

    def validate(self, attrs):
        attrs = super().validate(attrs)
        upload = attrs["file"]
        stem = upload.name.rsplit("/", 1)[-1].rsplit(".", 1)[0]
        try:
            graph, fmt = services.read_graph(upload.read(), attrs.get("format"), name=attrs.get("name") or stem)
        except InputError as exc:
            raise serializers.ValidationError({"file": [f"{upload.name}: {exc}"]}) from exc
        if attrs.get("name"):
            graph.name = attrs["name"]
        attrs["graph"], attrs["source_format"] = graph, fmt
        return attrs

    def create(self, validated):
        user = self._user()
        row = RosGraph(
            fleet=validated["fleet"],
            name=validated["graph"].name,
            description=validated["description"],
            source_format=validated["source_format"],
            created_by=user if user is not None and user.is_authenticated else None,
        )
        row.set_graph(validated["graph"])
        row.save()
        return row


# ---- clustering -------------------------------------------------------------------------------------------
class ImageOptionsSerializer(ScopedSerializer):
    distro_image = serializers.CharField(required=False, max_length=200)
    ros_distro = serializers.CharField(required=False, max_length=40)
    distro_mib = serializers.FloatField(required=False, min_value=0)
    platforms = serializers.ListField(child=serializers.CharField(), required=False, allow_empty=False)
    repository = serializers.CharField(required=False, allow_blank=True, max_length=200)
    tag = serializers.CharField(required=False, max_length=128)

    def validate_platforms(self, value):
        try:
            return [normalize_arch(p, "platforms") for p in value]
        except InputError as exc:
            raise serializers.ValidationError(str(exc)) from exc

    # These values are written into build.sh and the Dockerfiles: each must follow its grammar.
    @staticmethod
    def _grammar(problem: str | None, value):
        if problem is not None:
            raise serializers.ValidationError(problem)
        return value

    def validate_distro_image(self, value):
        return self._grammar(artifact_names.reference_problem(value), value)

    def validate_ros_distro(self, value):
        return self._grammar(artifact_names.ros_distro_problem(value), value)

    def validate_repository(self, value):
        return self._grammar(artifact_names.repository_problem(value) if value else None, value)

    def validate_tag(self, value):
        return self._grammar(artifact_names.tag_problem(value), value)


class ClusterRequestSerializer(ScopedSerializer):
    """Cluster the graph's ROS nodes into N containers (Listing 3.20), or as many as Eq. 3.13 allows."""

    containers = serializers.IntegerField(
        min_value=1,
        max_value=limits.get().nodes,
        error_messages=at_most("containers")
        | {"min_value": "the number of containers must be a positive integer (greater than or equal to {min_value})"},
        required=False,
        help_text="number of containers N",
    )
    memory_mib = serializers.FloatField(min_value=0, required=False, help_text="memory for containers (Eq. 3.13)")
    overhead_mib = serializers.FloatField(min_value=0, required=False, help_text="memory cost of one container")
    mode = serializers.ChoiceField(choices=MODES, default="per_topic", help_text="Eq. 3.12 reading")
    max_cluster_share = serializers.FloatField(min_value=0, max_value=1, required=False, allow_null=True)
    max_cluster_memory_mib = serializers.FloatField(min_value=0, required=False, allow_null=True)
    images = ImageOptionsSerializer(required=False, help_text="image plan options (Fig. 3.24)")

    def validate(self, attrs):
        memory, overhead = attrs.get("memory_mib"), attrs.get("overhead_mib")
        if (memory is None) != (overhead is None):
            raise serializers.ValidationError({"memory_mib": ["Eq. 3.13 needs both memory_mib and overhead_mib"]})
        try:
            bound = max_containers(memory, overhead) if memory is not None else None
        except InputError as exc:
            raise input_error(exc, "memory_mib") from exc
        n = attrs.get("containers")
        if n is None and bound is None:
            raise serializers.ValidationError(
                {"containers": ["give the number of containers, or memory_mib and overhead_mib (Eq. 3.13)"]}
            )
        if n is not None and bound is not None and n > bound:
            raise serializers.ValidationError(
                {"containers": [f"{n} containers exceed the Eq. 3.13 bound floor({memory:g} / {overhead:g}) = {bound}"]}
            )
        if attrs.get("max_cluster_share") == 0:
            raise serializers.ValidationError({"max_cluster_share": ["must lie in (0, 1]"]})
        return attrs

    def job_arguments(self, rosgraph: RosGraph) -> dict:
        data = {k: v for k, v in self.validated_data.items() if v is not None}
        return {"rosgraph": rosgraph.pk, **data}


class ClusteringSerializer(ScopedModelSerializer):
    fleet = serializers.SlugRelatedField(slug_field="slug", read_only=True)
    rosgraph_name = serializers.CharField(source="rosgraph.name", read_only=True)
    containers = serializers.SerializerMethodField()
    container_bandwidth = serializers.SerializerMethodField(help_text="bytes/s between each pair of containers")
    dockerfiles = serializers.SerializerMethodField(help_text="archive URLs, when there is an image plan")

    class Meta:
        model = Clustering
        fields = [
            "id",
            "fleet",
            "rosgraph",
            "rosgraph_name",
            "job",
            "requested_containers",
            "container_count",
            "params",
            "containers",
            "inter_container_bandwidth",
            "intra_container_bandwidth",
            "container_bandwidth",
            "result",
            "images",
            "disk_before_mib",
            "disk_after_mib",
            "dockerfiles",
            "created",
        ]
        read_only_fields = fields

    def get_containers(self, obj) -> list[dict]:
        return obj.containers

    def get_container_bandwidth(self, obj) -> list[dict]:
        from continuum.engine.containers.superclustering import container_bandwidth

        weights = container_bandwidth(obj.graph, obj.groups(), obj.result.get("params", {}).get("mode", "per_topic"))
        return [{"a": a, "b": b, "bytes_per_s": w} for (a, b), w in sorted(weights.items())]

    def get_dockerfiles(self, obj) -> dict[str, str] | None:
        if not obj.images:
            return None
        request = self.context.get("request")
        url = f"/api/v1/clusterings/{obj.pk}/dockerfiles/"
        if request is not None:
            url = request.build_absolute_uri(url)
        return {kind: f"{url}?archive={kind}" for kind in services.ARCHIVES}


class ClusteringListSerializer(ClusteringSerializer):
    class Meta(ClusteringSerializer.Meta):
        fields = [
            "id",
            "fleet",
            "rosgraph",
            "rosgraph_name",
            "requested_containers",
            "container_count",
            "inter_container_bandwidth",
            "intra_container_bandwidth",
            "disk_before_mib",
            "disk_after_mib",
            "created",
        ]


# ---- placement --------------------------------------------------------------------------------------------
class PlaceRequestSerializer(ScopedSerializer):
    """Place containers on the nodes of a cluster: a clustering's containers (with per-container
    ``overrides``) or a ``continuum.containers/v1`` document (optionally with the ROS graph for bandwidth)."""

    cluster = VisibleClusterField()
    policy = serializers.ChoiceField(choices=[*POLICIES, *ALIASES], default="superclustering")
    clustering = VisibleRelatedField(Clustering, required=False)
    containers = serializers.JSONField(required=False, help_text="a continuum.containers/v1 document")
    rosgraph = VisibleRelatedField(RosGraph, required=False, help_text="with 'containers': bandwidth by Def. 3.2.1")
    overrides = serializers.DictField(
        required=False, default=dict, help_text="container -> {cpu, memory_mib, priority, archs, node, tolerations...}"
    )
    archs = serializers.ListField(child=serializers.CharField(), required=False, allow_empty=False)
    weights = serializers.DictField(child=serializers.FloatField(min_value=0), required=False)
    seed = serializers.IntegerField(default=0, help_text="tie-break seed of the default-Kubernetes policy")
    overhead_mib = serializers.FloatField(min_value=0, default=0.0, help_text="runtime memory per container")
    compare = serializers.BooleanField(default=True, help_text="also run the other policy for comparison")
    drivers_on_robot = serializers.BooleanField(
        default=lambda: settings.CONTINUUM_DRIVERS_ON_ROBOT,
        help_text="keep containers holding driver-level (or robot-pinned) ROS nodes on the robot's boards",
    )
    robot_label = serializers.CharField(
        default=lambda: settings.CONTINUUM_ROBOT_LABEL,
        max_length=317,
        help_text="key=value label of the robot's boards (default zone=robot)",
    )

    def validate_robot_label(self, value):
        try:
            return "=".join(parse_label(value))
        except InputError as exc:
            raise serializers.ValidationError(str(exc)) from exc

    def validate_weights(self, value):
        unknown = sorted(set(value) - set(SCORERS))
        if unknown:
            raise serializers.ValidationError(f"unknown scoring policy {unknown[0]!r} (one of {', '.join(SCORERS)})")
        return value

    def validate(self, attrs):
        clustering, doc = attrs.get("clustering"), attrs.get("containers")
        if (clustering is None) == (doc is None):
            raise serializers.ValidationError({"clustering": ["give exactly one of 'clustering' and 'containers'"]})
        fleet_id = clustering.fleet_id if clustering is not None else attrs["cluster"].fleet_id
        if attrs["cluster"].fleet_id != fleet_id:
            raise serializers.ValidationError({"cluster": ["the cluster belongs to another fleet"]})
        rosgraph = attrs.get("rosgraph")
        if rosgraph is not None and (clustering is not None or rosgraph.fleet_id != fleet_id):
            raise serializers.ValidationError({"rosgraph": ["only with 'containers', and of the cluster's fleet"]})
        # Check the whole input with the engine now: a bad request is a 400, not a failed job.
        try:
            if clustering is not None:
                services.clustering_workload(clustering, archs=attrs.get("archs"), overrides=attrs["overrides"])
            else:
                if attrs["overrides"] or attrs.get("archs"):
                    raise InputError("'overrides' and 'archs' go with a clustering; edit the document", "overrides")
                services.resolve_workload(doc, rosgraph.graph if rosgraph else None)
            services.engine_cluster(attrs["cluster"])
        except InputError as exc:
            raise input_error(exc, "containers") from exc
        return attrs

    def job_arguments(self) -> dict:
        data = dict(self.validated_data)
        args = {"cluster": data["cluster"].pk, "policy": ALIASES.get(data["policy"], data["policy"])}
        if data.get("clustering") is not None:
            args["clustering"] = data["clustering"].pk
            if data["overrides"]:
                args["overrides"] = data["overrides"]
            if data.get("archs"):
                args["archs"] = data["archs"]
        else:
            args["containers"] = data["containers"]
            if data.get("rosgraph") is not None:
                args["rosgraph"] = data["rosgraph"].pk
        for key in ("weights", "seed", "overhead_mib", "compare", "drivers_on_robot", "robot_label"):
            if data.get(key) is not None:
                args[key] = data[key]
        return args

    def fleet(self):
        data = self.validated_data
        return data["clustering"].fleet if data.get("clustering") is not None else data["cluster"].fleet


class ContainerDeploymentSerializer(ScopedModelSerializer):
    class Meta:
        model = ContainerDeployment
        fields = ["container", "node", "deployment", "namespace", "state", "message", "updated",
                  "pod_name", "pod_phase", "pod_node", "pod_event", "pod_state_at"]  # fmt: skip
        read_only_fields = fields


class PlacementSerializer(ScopedModelSerializer):
    fleet = serializers.SlugRelatedField(slug_field="slug", read_only=True)
    node_traffic = serializers.SerializerMethodField(help_text="bytes/s between each pair of nodes")
    deployments = ContainerDeploymentSerializer(many=True, read_only=True)
    warnings = serializers.SerializerMethodField(
        help_text="what the operator should know: driver-level ROS nodes placed off the robot"
    )

    class Meta:
        model = Placement
        fields = [
            "id",
            "fleet",
            "clustering",
            "rosgraph",
            "cluster",
            "job",
            "policy",
            "params",
            "placed_count",
            "pending_count",
            "inter_node_bandwidth",
            "baseline",
            "node_traffic",
            "warnings",
            "plan",
            "containers",
            "cluster_document",
            "deployments",
            "created",
        ]
        read_only_fields = fields

    def get_node_traffic(self, obj) -> list[dict]:
        return services.node_traffic(obj)

    def get_warnings(self, obj) -> list[dict]:
        return services.placement_warnings(obj)


class PlacementListSerializer(PlacementSerializer):
    class Meta(PlacementSerializer.Meta):
        fields = [
            "id",
            "fleet",
            "clustering",
            "rosgraph",
            "cluster",
            "policy",
            "placed_count",
            "pending_count",
            "inter_node_bandwidth",
            "baseline",
            "created",
        ]
