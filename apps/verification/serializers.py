from django.db import transaction
from rest_framework import serializers

from apps.clusters.models import ComputeNode
from apps.clusters.serializers import VisibleClusterField
from apps.tenancy.api import FleetOwnedSerializer, ScopedModelSerializer, ScopedSerializer, VisibleRelatedField
from continuum.engine.core.errors import InputError
from continuum.engine.verification.monitor_milp import DEFAULT_WORK_LIMIT, MonitorStats

from . import services
from .models import AllocationRun, Assertion, Handler, MigrationEvent, Monitor, MonitorVerdict, Violation


class AssertionSerializer(FleetOwnedSerializer):
    status = serializers.CharField(read_only=True)
    monitor_count = serializers.IntegerField(source="monitors.count", read_only=True)

    class Meta:
        model = Assertion
        fields = [
            "id",
            "fleet",
            "name",
            "text",
            "constants",
            "description",
            "skeleton",
            "placeholders",
            "variables",
            "status",
            "monitor_count",
            "created",
            "updated",
        ]
        read_only_fields = ["skeleton", "placeholders", "variables", "created", "updated"]
        validators = []  # (fleet, name) uniqueness is checked in validate(), with the fleet defaulted first

    def validate(self, attrs):
        attrs = super().validate(attrs)
        probe = Assertion(
            text=attrs.get("text", getattr(self.instance, "text", "")),
            constants=attrs.get("constants", getattr(self.instance, "constants", {})),
        )
        try:
            probe.compile()  # a syntax error names the column: "column 12: expected ..."
        except InputError as exc:
            raise serializers.ValidationError({exc.field if exc.field == "constants" else "text": [str(exc)]}) from None
        fleet = attrs.get("fleet") or self.instance.fleet
        name = attrs.get("name", getattr(self.instance, "name", None))
        clash = Assertion.objects.filter(fleet=fleet, name=name).exclude(pk=getattr(self.instance, "pk", None))
        if clash.exists():
            raise serializers.ValidationError({"name": [f"fleet {fleet.slug!r} already has assertion {name!r}"]})
        return attrs


class VisibleAssertion(VisibleRelatedField):
    model = Assertion


class VisibleNode(VisibleRelatedField):
    model = ComputeNode


class MonitorSerializer(FleetOwnedSerializer):
    assertion = VisibleAssertion()
    cluster = VisibleClusterField()
    node = VisibleNode(required=False, allow_null=True)
    node_name = serializers.CharField(source="node.name", read_only=True, default=None)

    class Meta:
        model = Monitor
        fields = [
            "id",
            "fleet",
            "assertion",
            "cluster",
            "name",
            "tolerant",
            "node",
            "node_name",
            "verdict",
            "events",
            "violation_count",
            "active_instances",
            "cpu",
            "created",
            "updated",
        ]
        read_only_fields = ["verdict", "events", "violation_count", "active_instances", "cpu", "created", "updated"]
        validators = []  # (cluster, name) uniqueness is checked in validate()

    def validate(self, attrs):
        attrs = super().validate(attrs)
        fleet = attrs.get("fleet") or self.instance.fleet
        assertion = attrs.get("assertion") or self.instance.assertion
        cluster = attrs.get("cluster") or self.instance.cluster
        node = attrs.get("node", getattr(self.instance, "node", None))
        if assertion.fleet_id != fleet.pk:
            raise serializers.ValidationError(
                {"assertion": [f"assertion {assertion.name!r} is not in fleet {fleet.slug!r}"]}
            )
        if cluster.fleet_id != fleet.pk:
            raise serializers.ValidationError({"cluster": [f"cluster {cluster.name!r} is not in fleet {fleet.slug!r}"]})
        if node is not None and node.cluster_id != cluster.pk:
            raise serializers.ValidationError({"node": [f"node {node.name!r} is not in cluster {cluster.name!r}"]})
        name = attrs.get("name", getattr(self.instance, "name", None))
        clash = Monitor.objects.filter(cluster=cluster, name=name).exclude(pk=getattr(self.instance, "pk", None))
        if clash.exists():
            raise serializers.ValidationError({"name": [f"cluster {cluster.name!r} already has monitor {name!r}"]})
        return attrs


class HandlerSerializer(ScopedModelSerializer):
    name = serializers.CharField(source="node.name", read_only=True)
    alive = serializers.BooleanField(read_only=True)

    class Meta:
        model = Handler
        fields = [
            "id",
            "cluster",
            "node",
            "name",
            "alive",
            "is_coordinator",
            "last_seen",
            "threshold",
            "delay_ms",
            "free_cpu",
            "verification_cpu",
            "monitor_cpu",
            "active",
        ]
        read_only_fields = [
            "cluster",
            "node",
            "is_coordinator",
            "last_seen",
            "free_cpu",
            "verification_cpu",
            "monitor_cpu",
            "active",
        ]


class HandlerSyncSerializer(ScopedSerializer):
    cluster = VisibleClusterField()


class ViolationSerializer(ScopedModelSerializer):
    monitor_name = serializers.CharField(source="monitor.name", read_only=True)
    assertion = serializers.IntegerField(source="monitor.assertion_id", read_only=True)

    class Meta:
        model = Violation
        fields = [
            "id",
            "monitor",
            "monitor_name",
            "assertion",
            "time_ms",
            "instance_start_ms",
            "event",
            "handler",
            "created",
        ]


class MonitorVerdictSerializer(ScopedModelSerializer):
    class Meta:
        model = MonitorVerdict
        fields = ["id", "monitor", "verdict", "counters", "pending", "handler", "created"]


class EventBatchSerializer(ScopedSerializer):
    """Events of the system under verification: ``[variable, value, timestamp_ms]`` triples (or objects with
    those keys), for one cluster; ``now`` (ms, optional) also advances the monitors' clock."""

    cluster = VisibleClusterField()
    events = serializers.JSONField()
    now = serializers.FloatField(required=False, min_value=0)

    def validate_events(self, value):
        try:
            return services.parse_events(value)
        except InputError as exc:
            raise serializers.ValidationError(str(exc)) from None


class MigrationEventSerializer(ScopedModelSerializer):
    class Meta:
        model = MigrationEvent
        fields = ["id", "run", "monitor", "monitor_name", "source", "target", "t", "events_moved", "created"]


class AllocationRunSerializer(ScopedModelSerializer):
    migration_count = serializers.IntegerField(source="migrations.count", read_only=True)

    class Meta:
        model = AllocationRun
        fields = [
            "id",
            "fleet",
            "cluster",
            "job",
            "source",
            "scenario",
            "series",
            "t",
            "n_monitors",
            "n_nodes",
            "n_topics",
            "status",
            "feasible",
            "objective",
            "solve_time_ms",
            "makespan_ms",
            "applied",
            "migration_count",
            "nodes",
            "result",
            "created",
        ]
        read_only_fields = fields


class AllocationRequestSerializer(ScopedSerializer):
    """Start the MILP on a cluster's statistics (``cluster``) or on a ``stats`` document."""

    cluster = VisibleClusterField(required=False)
    stats = serializers.JSONField(required=False)
    apply = serializers.BooleanField(default=False, help_text="move the monitors (cluster only)")
    work_limit = serializers.IntegerField(
        default=DEFAULT_WORK_LIMIT,
        min_value=1,
        max_value=1_000_000,
        help_text="branch-and-bound nodes per solve: the same input gives the same allocation under any load",
    )
    time_limit = serializers.FloatField(
        required=False,
        min_value=0.1,
        max_value=600,
        help_text="optional wall-clock cap in seconds (the allocation may then depend on the machine's load)",
    )

    def validate(self, attrs):
        if ("cluster" in attrs) == ("stats" in attrs):
            raise serializers.ValidationError({"non_field_errors": ["give either 'cluster' or 'stats'"]})
        if "stats" in attrs:
            try:
                MonitorStats.from_dict(attrs["stats"])
            except InputError as exc:
                raise serializers.ValidationError({"stats": [str(exc)]}) from None
        if attrs.get("apply") and "cluster" not in attrs:
            raise serializers.ValidationError({"apply": ["only a cluster's allocation can be applied"]})
        if "cluster" in attrs:
            try:
                with transaction.atomic():
                    MonitorStats.from_dict(services.stats_document(attrs["cluster"]))
                    transaction.set_rollback(True)  # only a check: the handler rows are made by the job
            except InputError as exc:
                raise serializers.ValidationError({"cluster": [str(exc)]}) from None
        return attrs

    def job_arguments(self) -> dict:
        data = self.validated_data
        args = {"apply": data["apply"], "work_limit": data["work_limit"]}
        if data.get("time_limit") is not None:
            args["time_limit"] = data["time_limit"]
        if "cluster" in data:
            args["cluster"] = data["cluster"].pk
        else:
            args["stats"] = data["stats"]
        return args

    def fleet(self, request):
        if "cluster" in self.validated_data:
            return self.validated_data["cluster"].fleet
        from apps.tenancy.api import default_fleet

        return default_fleet(request)


class SimulationRequestSerializer(ScopedSerializer):
    scenario = serializers.ChoiceField(["kairos", "synthetic"], default="kairos")
    duration_s = serializers.FloatField(required=False, min_value=1, max_value=600)
    time_limit = serializers.FloatField(required=False, min_value=0.05, max_value=10)

    def job_arguments(self) -> dict:
        """The verification_simulation job's arguments (``apps/verification/jobs.py``)."""
        return dict(self.validated_data)
