from drf_spectacular.utils import extend_schema_field
from rest_framework import serializers

from apps.tenancy.api import ScopedModelSerializer

from . import joblog
from .models import Job, JobLogLine


class JobLogLineSerializer(ScopedModelSerializer):
    """One line of a job's log: when, the progress then (if any) and what happened."""

    class Meta:
        model = JobLogLine
        fields = ["at", "progress", "text"]
        read_only_fields = fields


class JobSerializer(ScopedModelSerializer):
    fleet = serializers.SlugRelatedField(slug_field="slug", read_only=True)
    created_by = serializers.StringRelatedField()
    url = serializers.HyperlinkedIdentityField(view_name="api:job-detail")
    duration = serializers.FloatField(read_only=True, allow_null=True)
    title = serializers.CharField(read_only=True, help_text="what the job does, in words")
    cancel_unavailable = serializers.SerializerMethodField(
        help_text="why POST .../cancel/ would be refused now ('' when the job can be cancelled)"
    )
    retry_unavailable = serializers.SerializerMethodField(
        help_text="why POST .../retry/ would be refused now ('' when the job can be retried)"
    )
    waiting_notice = serializers.SerializerMethodField(
        help_text="a pending job no worker has picked up for a minute: how long, and what is ahead of it ('' else)"
    )

    class Meta:
        model = Job
        fields = [
            "id",
            "url",
            "fleet",
            "kind",
            "title",
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
            "cancel_requested",
            "cancel_unavailable",
            "retry_unavailable",
            "waiting_notice",
            "retry_of",
            "created",
            "queued",
            "started",
            "finished",
            "duration",
        ]
        read_only_fields = fields

    def get_cancel_unavailable(self, job: Job) -> str:
        return job.cancel_unavailable()

    def get_retry_unavailable(self, job: Job) -> str:
        return job.retry_unavailable()

    def get_waiting_notice(self, job: Job) -> str:
        return job.waiting_notice()


class JobDetailSerializer(JobSerializer):
    """One job with its log (the newest lines, oldest first; bounded, see apps/jobs/joblog.py)."""

    log = serializers.SerializerMethodField()

    class Meta(JobSerializer.Meta):
        fields = [*JobSerializer.Meta.fields, "log"]
        read_only_fields = fields

    @extend_schema_field(JobLogLineSerializer(many=True))
    def get_log(self, job: Job) -> list[dict]:
        return JobLogLineSerializer(joblog.lines(job.pk), many=True).data
