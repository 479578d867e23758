from django.db import transaction
from rest_framework import serializers
from rest_framework.exceptions import PermissionDenied

from apps.kube.credentials import Undecryptable
from apps.kube.kubeconfig import KubeconfigError, validate
from apps.tenancy.api import (
    DefaultFleetMixin,
    FleetField,
    FleetOwnedSerializer,
    ScopedModelSerializer,
    ScopedSerializer,
    VisibleRelatedField,
)
from apps.tenancy.bounds import at_most, at_most_items
from apps.tenancy.models import FleetToken
from continuum.engine.core import limits
from continuum.engine.core.cluster import FORMAT as CLUSTER_FORMAT
from continuum.engine.core.cluster import Cluster as EngineCluster
from continuum.engine.core.errors import InputError
from continuum.engine.core.unique import duplicates

from .models import Cluster, ComputeNode, Link

LIMITS = limits.get()
INT32_MAX = 2**31 - 1
CREDENTIALS_PERMISSION = "clusters.change_cluster_credentials"
CREDENTIAL_FIELDS = ("kubeconfig", "kube_context")


def may_set_credentials(request) -> bool:
    """Whether the caller may set Kubernetes credentials: an operator signed in as themselves with the
    ``clusters.change_cluster_credentials`` permission. Never a fleet token: tokens are robots, and a robot
    that could set a kubeconfig could point the server at any host with any credentials."""
    user = getattr(request, "user", None)
    if user is None or not user.is_authenticated or isinstance(getattr(request, "auth", None), FleetToken):
        return False
    return user.has_perm(CREDENTIALS_PERMISSION)


def check_credentials(request, attrs: dict, instance: Cluster | None) -> None:
    """403 when the credentials change without the permission; 400 naming the field when the kubeconfig is
    refused (apps.kube.kubeconfig). Runs before anything is stored."""
    from apps.kube.gateway import server_policy  # the gateway imports the cluster models

    current = {f: (getattr(instance, f) if instance is not None else "") for f in CREDENTIAL_FIELDS}
    changed = [f for f in CREDENTIAL_FIELDS if f in attrs and attrs[f] != current[f]]
    if not changed:
        return
    if not may_set_credentials(request):
        raise PermissionDenied(
            {
                changed[0]: [
                    f"setting a cluster's Kubernetes credentials needs the permission {CREDENTIALS_PERMISSION} "
                    "(an operator's account; fleet tokens never have it)"
                ]
            }
        )
    text = attrs.get("kubeconfig", current["kubeconfig"])
    if not text:
        return
    if isinstance(text, Undecryptable):
        raise serializers.ValidationError(
            {"kubeconfig": ["the stored kubeconfig cannot be decrypted with the current key: set it again"]}
        )
    try:
        validate(text, attrs.get("kube_context", current["kube_context"]), server_policy())
    except KubeconfigError as exc:
        field = "kube_context" if exc.path == "kube_context" else "kubeconfig"
        raise serializers.ValidationError({field: [str(exc)]}) from exc


def check_namespace_owner(attrs: dict, instance: Cluster | None, fleet_id: int | None) -> None:
    """400 when another fleet's cluster already uses this namespace of the same Kubernetes API (issue 25): the
    live pod state, the pushes and the RT scheduler of a cluster act on the pods of its namespace, so two fleets
    that share one would see, and act on, each other's pods. The namespace is Continuum's per cluster, owned by
    one fleet. Servers are compared as the kubeconfigs name them (never resolved)."""
    from apps.kube.gateway import server_policy

    text = attrs.get("kubeconfig", instance.kubeconfig if instance is not None else "")
    namespace = attrs.get("namespace", instance.namespace if instance is not None else "")
    if not text or not namespace or isinstance(text, Undecryptable) or fleet_id is None:
        return
    context = attrs.get("kube_context", instance.kube_context if instance is not None else "")
    try:
        server = validate(text, context, server_policy()).server
    except KubeconfigError:
        return  # check_credentials names the problem
    others = Cluster.objects.filter(namespace=namespace).exclude(fleet_id=fleet_id)
    if instance is not None:
        others = others.exclude(pk=instance.pk)
    for other in others.only("kubeconfig", "kube_context"):
        stored = other.kubeconfig
        if not stored or isinstance(stored, Undecryptable):
            continue
        try:
            if validate(stored, other.kube_context, server_policy()).server == server:
                taken = f"namespace {namespace!r} of this Kubernetes API belongs to another fleet's cluster"
                raise serializers.ValidationError({"namespace": [f"{taken}: choose another namespace"]})
        except KubeconfigError:
            continue


class ClusterSerializer(FleetOwnedSerializer):
    node_count = serializers.IntegerField(source="nodes.count", read_only=True)
    kubeconfig = serializers.CharField(
        write_only=True, required=False, allow_blank=True, style={"base_template": "textarea.html"}
    )
    has_kubeconfig = serializers.SerializerMethodField()

    class Meta:
        model = Cluster
        fields = [
            "id",
            "fleet",
            "name",
            "description",
            "kubeconfig",
            "has_kubeconfig",
            "kube_context",
            "namespace",
            "default_bandwidth_mbps",
            "default_latency_ms",
            "node_count",
            "last_synced",
            "created",
        ]
        read_only_fields = ["last_synced", "created"]

    def get_has_kubeconfig(self, obj) -> bool:
        return bool(obj.kubeconfig)

    def validate(self, attrs):
        attrs = super().validate(attrs)
        check_credentials(self.context.get("request"), attrs, self.instance)
        fleet = attrs.get("fleet") or getattr(self.instance, "fleet", None)
        check_namespace_owner(attrs, self.instance, getattr(fleet, "pk", None))
        return attrs


class VisibleClusterField(VisibleRelatedField):
    model = Cluster


#: The planning capacity a caller may declare (node sync then keeps it; see apps.clusters.kube.row_fields).
CAPACITY_FIELDS = frozenset({"cpu", "memory_mib", "storage_mib"})


class ComputeNodeSerializer(ScopedModelSerializer):
    cluster = VisibleClusterField()
    # A list of names, never null (the column is NOT NULL; "null" used to reach the database).
    accelerators = serializers.ListField(
        child=serializers.CharField(max_length=64), required=False, max_length=64, help_text='e.g. ["igpu"]'
    )

    class Meta:
        model = ComputeNode
        fields = [
            "id",
            "cluster",
            "name",
            "arch",
            "cpu",
            "memory_mib",
            "storage_mib",
            "capacity_source",
            "reported_cpu",
            "reported_memory_mib",
            "reported_storage_mib",
            "accelerators",
            "processor_class",
            "speed",
            "rt",
            "criticality",
            "rt_threshold",
            "labels",
            "taints",
            "status",
        ]
        # What Kubernetes reports is written by node sync only; capacity_source follows what the caller sets.
        read_only_fields = ["capacity_source", "reported_cpu", "reported_memory_mib", "reported_storage_mib"]
        extra_kwargs = {"cpu": {"max_value": LIMITS.cores, "error_messages": at_most("cpu")}}

    def update(self, instance, validated_data):
        if CAPACITY_FIELDS & set(validated_data):  # declared now: node sync keeps it from here on
            validated_data["capacity_source"] = ComputeNode.Capacity.DECLARED
        return super().update(instance, validated_data)

    def validate_taints(self, value):
        if not isinstance(value, list) or not all(
            isinstance(t, dict) and t.get("key") and t.get("effect") for t in value
        ):
            raise serializers.ValidationError('a list of {"key", "value", "effect"} objects')
        return value

    def validate_labels(self, value):
        if not isinstance(value, dict) or not all(isinstance(v, str) for v in value.values()):
            raise serializers.ValidationError("a map of label name to string value")
        return value


class LinkSerializer(ScopedModelSerializer):
    cluster = VisibleClusterField()

    class Meta:
        model = Link
        fields = ["id", "cluster", "src", "dst", "bandwidth_mbps", "latency_ms"]

    def validate(self, attrs):
        attrs = super().validate(attrs)
        cluster = attrs.get("cluster") or self.instance.cluster
        for end in ("src", "dst"):
            node = attrs.get(end) or getattr(self.instance, end, None)
            if node is not None and node.cluster_id != cluster.pk:
                raise serializers.ValidationError({end: [f"node {node.name!r} is not in cluster {cluster.name!r}"]})
        if attrs.get("src") and attrs.get("src") == attrs.get("dst"):
            raise serializers.ValidationError({"dst": ["a link joins two different nodes"]})
        return attrs


class ClusterDocumentNodeSerializer(ScopedSerializer):
    """One node of a ``continuum.cluster/v1`` document."""

    name = serializers.CharField(max_length=253)
    arch = serializers.ChoiceField(ComputeNode.Arch.choices, default=ComputeNode.Arch.AMD64)
    cpu = serializers.FloatField(min_value=0, max_value=LIMITS.cores, default=1.0, error_messages=at_most("cpu"))
    # The columns are 32-bit integers; a larger number is a 400 here, not a database error.
    memory_mib = serializers.IntegerField(min_value=0, max_value=INT32_MAX, default=1024)
    storage_mib = serializers.IntegerField(min_value=0, max_value=INT32_MAX, default=0)
    accelerators = serializers.ListField(child=serializers.CharField(), default=list)
    processor_class = serializers.CharField(default="cpu", help_text="class that DAG task costs name")
    speed = serializers.FloatField(min_value=0.001, default=1.0)
    rt = serializers.BooleanField(default=False)
    criticality = serializers.ChoiceField(ComputeNode.Criticality.choices, required=False, allow_blank=True)
    rt_threshold = serializers.FloatField(min_value=0, required=False, allow_null=True)
    labels = serializers.DictField(child=serializers.CharField(allow_blank=True), default=dict)
    taints = serializers.ListField(child=serializers.DictField(), default=list)


class ClusterDocumentLinkSerializer(ScopedSerializer):
    src = serializers.CharField()
    dst = serializers.CharField()
    bandwidth_mbps = serializers.FloatField(min_value=0.001)
    latency_ms = serializers.FloatField(min_value=0, default=0.0)


#: Rows per INSERT of a cluster document's nodes and links (SQLite allows 32,766 parameters a statement).
BULK_BATCH = 500


class ClusterImportSerializer(DefaultFleetMixin, ScopedSerializer):
    """A ``continuum.cluster/v1`` document that creates a cluster with its nodes and links at once."""

    fleet = FleetField(required=False)
    name = serializers.CharField(max_length=100)
    description = serializers.CharField(required=False, allow_blank=True, default="")
    kubeconfig = serializers.CharField(required=False, allow_blank=True, default="")
    kube_context = serializers.CharField(required=False, allow_blank=True, default="")
    namespace = serializers.CharField(required=False, max_length=63, default="continuum")
    # The list lengths are checked before any node is validated (a 400,000-node document took minutes).
    nodes = ClusterDocumentNodeSerializer(
        many=True, allow_empty=False, max_length=LIMITS.nodes, error_messages=at_most_items("nodes")
    )
    links = ClusterDocumentLinkSerializer(
        many=True, default=list, max_length=LIMITS.links, error_messages=at_most_items("links")
    )

    def to_internal_value(self, data):
        # The limits in force now (an override may be lower than the one the fields were built with).
        lim = limits.get()
        for key, maximum in (("nodes", lim.nodes), ("links", lim.links)):
            items = data.get(key) if hasattr(data, "get") else None
            if isinstance(items, list) and len(items) > maximum:
                raise serializers.ValidationError({key: [f"{key}: at most {maximum:,} (got {len(items):,})"]})
        return super().to_internal_value(data)

    def validate(self, attrs):
        attrs = super().validate(attrs)
        names = [n["name"] for n in attrs["nodes"]]
        dup = sorted(duplicates(names))
        if dup:
            raise serializers.ValidationError({"nodes": [f"duplicate node name {dup[0]!r}"]})
        known = set(names)  # a set: links x nodes list lookups were quadratic (issue 25)
        seen: dict[tuple[str, str], int] = {}
        for i, link in enumerate(attrs["links"]):
            for end in ("src", "dst"):
                if link[end] not in known:
                    raise serializers.ValidationError({"links": [f"links[{i}] refers to unknown node {link[end]!r}"]})
            if link["src"] == link["dst"]:
                raise serializers.ValidationError({"links": [f"links[{i}] joins node {link['src']!r} to itself"]})
            pair = (link["src"], link["dst"])
            if pair in seen:
                raise serializers.ValidationError(
                    {"links": [f"links[{i}] repeats links[{seen[pair]}] ({pair[0]} -> {pair[1]})"]}
                )
            seen[pair] = i
        self._read_as_the_engine_does(attrs)
        check_credentials(self.context.get("request"), attrs, None)
        check_namespace_owner(attrs, None, attrs["fleet"].pk)
        if Cluster.objects.filter(fleet=attrs["fleet"], name=attrs["name"]).exists():
            raise serializers.ValidationError(
                {"name": [f"fleet {attrs['fleet'].slug!r} already has cluster {attrs['name']!r}"]}
            )
        return attrs

    def _read_as_the_engine_does(self, attrs) -> None:
        """The document goes through the one parser of ``continuum.cluster/v1`` (``EngineCluster.from_dict``),
        so what the API stores is what every placer and command reads from the same file: ``"rt": "false"``
        is refused (not read as a boolean), a node's ``class`` is its processor class (``processor_class``
        is this API's older name for it), and ``sched_rt_runtime_us``/``sched_rt_period_us`` set the RT
        threshold when none is given. The fields above have checked types and bounds already."""
        raw_nodes = self.initial_data.get("nodes") or []
        document = {
            "format": self.initial_data.get("format", CLUSTER_FORMAT),
            "nodes": [_with_class(raw) for raw in raw_nodes],
            "links": self.initial_data.get("links") or [],
        }
        try:
            engine = EngineCluster.from_dict(document)
        except InputError as exc:
            field = exc.field if exc.field in self.fields else "nodes"
            raise serializers.ValidationError({field: [str(exc)]}) from None
        for node in attrs["nodes"]:
            parsed = engine.nodes[node["name"]]
            node["processor_class"] = parsed.cls
            if node.get("rt_threshold") is None and (parsed.sched_rt_runtime_us or parsed.sched_rt_period_us):
                node["rt_threshold"] = parsed.rt_capacity

    @transaction.atomic
    def create(self, validated):
        cluster = Cluster.objects.create(
            fleet=validated["fleet"],
            name=validated["name"],
            description=validated["description"],
            kubeconfig=validated["kubeconfig"],
            kube_context=validated["kube_context"],
            namespace=validated["namespace"],
        )
        # In bulk: one INSERT (and one audit entry, per object) each took the largest document allowed (5,000
        # nodes, 50,000 links) 64 s of CPU (benchmarks/input_limits.py). The trail records the cluster's
        # creation; its nodes and links are that document's.
        ComputeNode.objects.bulk_create(
            [ComputeNode(cluster=cluster, **raw) for raw in validated["nodes"]], batch_size=BULK_BATCH
        )
        nodes = {n.name: n.pk for n in ComputeNode.objects.filter(cluster=cluster).only("pk", "name")}
        links = [
            Link(
                cluster=cluster,
                src_id=nodes[link["src"]],
                dst_id=nodes[link["dst"]],
                bandwidth_mbps=link["bandwidth_mbps"],
                latency_ms=link["latency_ms"],
            )
            for link in validated["links"]
        ]
        Link.objects.bulk_create(links, batch_size=BULK_BATCH)
        return cluster


def _with_class(raw):
    """A node as the format spells it: ``processor_class`` (this API's name) is the format's ``class``."""
    if isinstance(raw, dict) and "processor_class" in raw and "class" not in raw:
        raw = {("class" if k == "processor_class" else k): v for k, v in raw.items()}
    return raw
