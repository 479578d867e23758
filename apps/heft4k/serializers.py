from rest_framework import serializers

from apps.tenancy.api import ScopedModelSerializer, ScopedSerializer
from continuum.engine.core.errors import InputError

from . import remapping
from .models import RemapEvent


class RemapRequestSerializer(ScopedSerializer):
    """Fail some nodes of a schedule: compute Algorithm 2's remap and, unless ``what_if``, apply it."""

    fail = serializers.ListField(
        child=serializers.CharField(), allow_empty=False, help_text="names of the nodes that fail"
    )
    what_if = serializers.BooleanField(default=False, help_text="compute and store only: push nothing")
    threshold = serializers.FloatField(
        required=False,
        allow_null=True,
        min_value=0.0,
        max_value=1.0,
        help_text="lost HEFT-rank share above which the whole DAG is remapped (default: CONTINUUM_REMAP_THRESHOLD)",
    )

    def validate(self, attrs):
        schedule = self.context["schedule"]
        try:
            remapping.check(schedule, attrs["fail"], attrs.get("threshold"))
        except InputError as exc:
            raise serializers.ValidationError({exc.field or "non_field_errors": [str(exc)]}) from exc
        return attrs

    def job_arguments(self) -> dict:
        data = self.validated_data
        return {
            "schedule": self.context["schedule"].pk,
            "fail": list(dict.fromkeys(data["fail"])),
            "what_if": data["what_if"],
            "threshold": data.get("threshold"),
            "trigger": RemapEvent.Trigger.WHAT_IF if data["what_if"] else RemapEvent.Trigger.API,
        }


class RemapEventSerializer(ScopedModelSerializer):
    fleet = serializers.SlugRelatedField(slug_field="slug", read_only=True)
    makespan_change = serializers.FloatField(read_only=True)
    pods_moved = serializers.IntegerField(read_only=True)
    can_apply = serializers.SerializerMethodField()

    class Meta:
        model = RemapEvent
        fields = [
            "id",
            "fleet",
            "application",
            "schedule",
            "new_schedule",
            "job",
            "trigger",
            "decision",
            "reason",
            "failed_nodes",
            "lost_tasks",
            "moved_tasks",
            "reniced_tasks",
            "critical_lost",
            "lost_share",
            "threshold",
            "makespan_before",
            "makespan_after",
            "makespan_change",
            "elapsed_ms",
            "status",
            "pods_moved",
            "pods",
            "push_ms",
            "message",
            "can_apply",
            "created",
            "applied",
        ]
        read_only_fields = fields

    def get_can_apply(self, obj) -> bool:
        return not remapping.cannot_apply(obj)
