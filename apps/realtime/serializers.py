import math

from django.db import transaction
from rest_framework import serializers

from apps.clusters.models import Cluster, ComputeNode
from apps.clusters.serializers import VisibleClusterField
from apps.tenancy.api import ScopedModelSerializer, ScopedSerializer
from continuum.engine.core.errors import InputError

from .models import (
    Monitoring,
    MonitoringReport,
    NodeTaint,
    RealTime,
    RealTimeWcet,
    RTDecision,
    RTEvent,
    RTPlan,
    RTPod,
    RTPolicy,
    engine_container,
)

#: Engine field names -> the API's.
ENGINE_FIELDS = {"wcet": "wcets", "memory_mib": "memory_mib", "containers": "wcets"}


def engine_error(exc: InputError, known: set[str]) -> serializers.ValidationError:
    name = ENGINE_FIELDS.get(exc.field or "", exc.field or "")
    return serializers.ValidationError({name if name in known else "non_field_errors": [str(exc)]})


class WcetSerializer(ScopedSerializer):
    node = serializers.CharField(max_length=253)
    wcet = serializers.FloatField(help_text="ms")


class RealTimeSerializer(ScopedModelSerializer):
    """A RealTime object (Listing 3.33). ``wcets`` keeps the order of ``spec.rtWcets``."""

    cluster = VisibleClusterField()
    namespace = serializers.CharField(max_length=63, required=False, help_text="default: the cluster's namespace")
    wcets = WcetSerializer(many=True)
    utilization = serializers.SerializerMethodField(help_text="WCET(node) / period per node")

    class Meta:
        model = RealTime
        fields = [
            "id",
            "cluster",
            "namespace",
            "name",
            "criticality",
            "period",
            "deadline",
            "wcets",
            "stateless",
            "cpu",
            "memory_mib",
            "warmup_ms",
            "utilization",
            "sync_state",
            "sync_error",
            "uid",
            "resource_version",
            "created",
            "updated",
        ]
        read_only_fields = ["sync_state", "sync_error", "uid", "resource_version", "created", "updated"]
        # The (cluster, namespace, name) uniqueness is checked in validate() with a message naming the object.
        validators = []

    def get_utilization(self, obj) -> dict[str, float]:
        return {w.node.name: w.wcet / obj.period for w in obj.wcets.all()} if obj.period else {}

    def to_representation(self, instance):
        data = super().to_representation(instance)
        data["wcets"] = [{"node": w.node.name, "wcet": w.wcet} for w in instance.wcets.all()]
        return data

    def validate_warmup_ms(self, value):
        if value is not None and not math.isfinite(value):
            raise serializers.ValidationError("must be a finite number of milliseconds")
        return value

    def validate(self, attrs):
        inst = self.instance
        cluster: Cluster = attrs.get("cluster") or inst.cluster
        if inst is not None and cluster.pk != inst.cluster_id:
            raise serializers.ValidationError({"cluster": ["a RealTime object cannot move to another cluster"]})

        def value(key, default=None):
            return attrs[key] if key in attrs else getattr(inst, key, default)

        namespace = value("namespace") or cluster.namespace
        attrs["namespace"] = namespace
        name = value("name")
        wcets = attrs.get("wcets")
        pairs = [(w["node"], w["wcet"]) for w in wcets] if wcets is not None else inst.wcet_pairs()
        nodes = {n.name: n for n in cluster.nodes.all()}
        try:
            engine_container(
                name,
                value("criticality"),
                value("period"),
                value("deadline"),
                pairs,
                stateless=value("stateless", False),
                cpu=value("cpu", 0.0),
                memory_mib=value("memory_mib", 0.0),
                known_nodes=nodes,
            )
        except InputError as exc:
            raise engine_error(exc, set(self.fields)) from exc
        clash = RealTime.objects.filter(cluster=cluster, namespace=namespace, name=name)
        if inst is not None:
            clash = clash.exclude(pk=inst.pk)
        if clash.exists():
            raise serializers.ValidationError(
                {"name": [f"cluster {cluster.name!r} already has RealTime {namespace}/{name}"]}
            )
        if wcets is not None:
            attrs["wcets"] = [(nodes[node], w) for node, w in pairs]
        return attrs

    @transaction.atomic
    def create(self, validated):
        wcets = validated.pop("wcets")
        row = RealTime.objects.create(**validated, dirty=True)
        self._write_wcets(row, wcets)
        return row

    @transaction.atomic
    def update(self, instance, validated):
        wcets = validated.pop("wcets", None)
        for key, value in validated.items():
            setattr(instance, key, value)
        instance.dirty = True
        instance.save()
        if wcets is not None:
            instance.wcets.all().delete()
            self._write_wcets(instance, wcets)
        return instance

    @staticmethod
    def _write_wcets(row, wcets) -> None:
        RealTimeWcet.objects.bulk_create(
            RealTimeWcet(realtime=row, node=node, wcet=w, position=i) for i, (node, w) in enumerate(wcets)
        )


class RealTimeImportSerializer(ScopedSerializer):
    cluster = VisibleClusterField()
    namespace = serializers.CharField(max_length=63, required=False, help_text="for objects that name none")
    yaml = serializers.CharField(help_text="RealTime objects (Listing 3.33); other kinds are skipped")


class ClusterRefSerializer(ScopedSerializer):
    cluster = VisibleClusterField()
    namespace = serializers.CharField(max_length=63, required=False, help_text="'*' for every namespace")


class WhatIfSerializer(ScopedSerializer):
    cluster = VisibleClusterField()
    realtimes = serializers.ListField(
        child=serializers.IntegerField(), required=False, help_text="RealTime ids (default: all of the cluster)"
    )
    containers = serializers.JSONField(required=False, help_text="a continuum.rtset/v1 document")
    params = serializers.DictField(required=False, help_text="k, b_score_argument, sort_tiebreak")
    with_bound = serializers.BooleanField(default=True, help_text="start from the pods bound now")


class RTPolicySerializer(ScopedModelSerializer):
    cluster = VisibleClusterField()

    class Meta:
        model = RTPolicy
        fields = [
            "id",
            "cluster",
            "threshold_period",
            "threshold_total",
            "update_frequency_hz",
            "eviction_policy",
            "linear_resource",
            "taint_duration_s",
            "cooldown_s",
            "recreate_orphans",
            "traffic",
            "k",
            "b_score_argument",
            "sort_tiebreak",
        ]

    def validate_cluster(self, cluster):
        # One policy per cluster (a OneToOneField): say so instead of failing on the unique index.
        taken = RTPolicy.objects.filter(cluster=cluster)
        if self.instance is not None:
            taken = taken.exclude(pk=self.instance.pk)
        if taken.exists():
            raise serializers.ValidationError(f"cluster {cluster.name!r} already has an RT policy; update that one")
        return cluster

    def validate(self, attrs):
        attrs = super().validate(attrs)
        probe = RTPolicy(**{**({f: getattr(self.instance, f) for f in self.Meta.fields[2:]} if self.instance else {}),
                            **{k: v for k, v in attrs.items() if k != "cluster"}})  # fmt: skip
        try:
            probe.monitor_policy()
            probe.scheduler_params()
        except InputError as exc:
            raise engine_error(exc, set(self.fields)) from exc
        if not isinstance(probe.traffic, dict) or not all(
            "|" in str(k) and isinstance(v, int | float) and v >= 0 for k, v in probe.traffic.items()
        ):
            raise serializers.ValidationError({"traffic": ['a map of "a|b" to a non-negative number']})
        return attrs


class MonitoringSerializer(ScopedModelSerializer):
    node = serializers.SlugRelatedField(slug_field="name", read_only=True)

    class Meta:
        model = Monitoring
        fields = ["id", "cluster", "name", "node", "container_name", "pod", "missed_period", "missed_total",
                  "received_at", "kube_synced"]  # fmt: skip
        read_only_fields = fields


class MonitoringReportSerializer(ScopedModelSerializer):
    class Meta:
        model = MonitoringReport
        fields = ["id", "cluster", "name", "node", "container_name", "pod", "missed_period", "missed_total",
                  "violation", "miss_at", "sent_at", "received_at", "source", "report_id",
                  "startup_overruns"]  # fmt: skip
        read_only_fields = fields


class ReportBatchSerializer(ScopedSerializer):
    """For the API docs only: the endpoint reads the body itself (it must be fast)."""

    cluster = serializers.IntegerField(required=False, help_text="default: the fleet's only cluster")
    reports = serializers.ListField(
        child=serializers.DictField(),
        help_text="Monitoring objects (Listing 3.37) or their spec: node, containerName, missedDeadlinesPeriod, "
        "missedDeadlinesTotal; optional pod, sentAt and missAt (RFC 3339 or epoch seconds) and report_id (or id: "
        "the report's idempotency key, unique per cluster; default: a digest of the report's content). A report "
        "whose id was seen before is acknowledged as a duplicate and not acted on again.",
    )


class RTEventSerializer(ScopedModelSerializer):
    class Meta:
        model = RTEvent
        fields = ["id", "cluster", "kind", "node", "container", "pod", "trigger", "missed_period", "missed_total",
                  "victim", "policy", "candidates", "message", "decision", "miss_at", "sent_at", "received_at",
                  "reconcile_done_at", "eviction_sent_at", "eviction_done_at", "eviction_error", "recreated",
                  "response", "response_ms"]  # fmt: skip
        read_only_fields = fields


class NodeTaintSerializer(ScopedModelSerializer):
    node = serializers.SlugRelatedField(slug_field="name", read_only=True)

    class Meta:
        model = NodeTaint
        fields = ["id", "cluster", "node", "key", "value", "effect", "event", "created", "expires_at", "applied_at",
                  "lifted_at", "error"]  # fmt: skip
        read_only_fields = fields


class RTPodSerializer(ScopedModelSerializer):
    class Meta:
        model = RTPod
        fields = ["id", "cluster", "namespace", "name", "uid", "node", "container_name", "scheduler_name", "realtime",
                  "criticality", "stateless", "cpu", "memory_mib", "utilization", "owned", "phase", "bound_at",
                  "deleted_at", "pod_event", "pod_state_at"]  # fmt: skip
        read_only_fields = fields


class RTDecisionSerializer(ScopedModelSerializer):
    class Meta:
        model = RTDecision
        fields = ["id", "cluster", "plan", "namespace", "pod", "pod_uid", "realtime", "criticality", "outcome", "node",
                  "score", "message", "decision", "created"]  # fmt: skip
        read_only_fields = fields


class RTPlanSerializer(ScopedModelSerializer):
    class Meta:
        model = RTPlan
        fields = ["id", "cluster", "kind", "job", "placed", "pending", "plan", "created"]
        read_only_fields = fields


class WhyNotQuerySerializer(ScopedSerializer):
    """``GET /api/v1/rt-decisions/{id}/why-not/``: one node (``?node=``) or every node of the cluster."""

    node = serializers.CharField(
        required=False, max_length=253, help_text="the node to explain (default: every node of the cluster)"
    )


class NodeVerdictSerializer(ScopedSerializer):
    node = serializers.CharField()
    rejected_by = serializers.CharField(allow_null=True, help_text="the filter that rejected the node, or null")
    reason = serializers.CharField(allow_blank=True)
    scores = serializers.DictField(child=serializers.FloatField())
    total = serializers.FloatField(allow_null=True)


class WhyNotSerializer(ScopedSerializer):
    """A decision's full explanation on demand, computed against the cluster as it is now."""

    decision = serializers.IntegerField()
    pod = serializers.CharField(help_text="namespace/name")
    chosen = serializers.CharField(allow_null=True, help_text="the node the decision chose, or null (pending)")
    as_of = serializers.DateTimeField()
    nodes = serializers.IntegerField(help_text="nodes in the cluster")
    verdicts = NodeVerdictSerializer(many=True)


class NodeAdmissionSerializer(ScopedModelSerializer):
    """A node's admissible RT bandwidth: the cluster file's, its kernel's, and which one RT-Kube's filter uses."""

    rt_capacity = serializers.FloatField(read_only=True, help_text="what RT-Kube's filter admits up to")
    rt_capacity_source = serializers.CharField(read_only=True)

    class Meta:
        model = ComputeNode
        fields = ["id", "cluster", "name", "cpu", "rt", "rt_threshold", "kernel_rt_capacity", "kernel_rt_source",
                  "kernel_reported_at", "rt_capacity", "rt_capacity_source"]  # fmt: skip
        read_only_fields = fields


class AdmissionReportSerializer(ScopedSerializer):
    """What ``python -m continuum.agent admission`` posts."""

    cluster = serializers.IntegerField(required=False, help_text="default: the fleet's only cluster")
    node = serializers.CharField(max_length=253)
    capacity = serializers.FloatField(min_value=0.0, max_value=4096.0, help_text="deadline bandwidth, in CPUs")
    cpus = serializers.ListField(child=serializers.IntegerField(min_value=0, max_value=65535), max_length=4096,
                                 required=False)  # fmt: skip
    source = serializers.CharField(max_length=200, required=False, allow_blank=True)
    kernel = serializers.CharField(max_length=100, required=False, allow_blank=True)

    def validate_capacity(self, value):
        if not math.isfinite(value):
            raise serializers.ValidationError("must be a finite number of CPUs")
        return value
