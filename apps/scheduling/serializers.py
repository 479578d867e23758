from rest_framework import serializers

from apps.clusters.serializers import VisibleClusterField
from continuum.engine import algorithms
from continuum.engine.errors import InputError
from continuum.engine.platform import Platform

from .models import Assignment, Schedule


class ScheduleRequestSerializer(serializers.Serializer):
    """Schedule an application on a cluster (its Ready nodes) or on a platform document."""

    algorithm = serializers.ChoiceField(choices=sorted(algorithms.SCHEDULERS), default="heft")
    cluster = VisibleClusterField(required=False)
    platform = serializers.JSONField(required=False, help_text="a continuum.platform/v1 document")
    params = serializers.DictField(required=False, default=dict, help_text="algorithm parameters, e.g. rank_mode")

    def validate_platform(self, value):
        try:
            Platform.from_dict(value)
        except InputError as exc:
            raise serializers.ValidationError(str(exc)) from exc
        return value

    def validate(self, attrs):
        if ("cluster" in attrs) == ("platform" in attrs):
            raise serializers.ValidationError({"cluster": ["give exactly one of 'cluster' and 'platform'"]})
        return attrs


class AssignmentSerializer(serializers.ModelSerializer):
    class Meta:
        model = Assignment
        fields = [
            "task",
            "frame",
            "processor",
            "core",
            "start",
            "finish",
            "niceness",
            "placement",
            "placement_message",
            "pod_name",
        ]


class ScheduleSerializer(serializers.ModelSerializer):
    """A stored schedule in the ``continuum.schedule/v1`` shape, plus its placement status per task."""

    format = serializers.SerializerMethodField()
    fleet = serializers.SlugRelatedField(slug_field="slug", read_only=True)
    assignments = AssignmentSerializer(many=True, read_only=True)

    class Meta:
        model = Schedule
        fields = [
            "id",
            "format",
            "fleet",
            "application",
            "cluster",
            "job",
            "algorithm",
            "params",
            "makespan",
            "ranks",
            "metrics",
            "platform",
            "assignments",
            "created",
        ]
        read_only_fields = fields

    def get_format(self, obj) -> str:
        return "continuum.schedule/v1"


class ScheduleListSerializer(ScheduleSerializer):
    class Meta(ScheduleSerializer.Meta):
        fields = ["id", "fleet", "application", "cluster", "job", "algorithm", "makespan", "created"]
