from rest_framework import serializers

from apps.tenancy.api import ScopedModelSerializer

from .models import Job


class JobSerializer(ScopedModelSerializer):
    fleet = serializers.SlugRelatedField(slug_field="slug", read_only=True)
    created_by = serializers.StringRelatedField()
    url = serializers.HyperlinkedIdentityField(view_name="api:job-detail")
    duration = serializers.FloatField(read_only=True, allow_null=True)

    class Meta:
        model = Job
        fields = [
            "id",
            "url",
            "fleet",
            "kind",
            "arguments",
            "created_by",
            "state",
            "progress",
            "message",
            "result",
            "result_url",
            "error",
            "attempts",
            "worker",
            "heartbeat",
            "interruption",
            "created",
            "started",
            "finished",
            "duration",
        ]
        read_only_fields = fields
