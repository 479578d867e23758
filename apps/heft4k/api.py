from drf_spectacular.utils import extend_schema
from rest_framework import status, viewsets
from rest_framework.decorators import action
from rest_framework.response import Response

from apps.heft4k.kinds import Heft4kJob
from apps.jobs.serializers import JobSerializer
from apps.jobs.services import start_job
from apps.scheduling.api import ScheduleViewSet
from apps.tenancy.api import FleetScopedMixin

from . import remapping
from .models import RemapEvent
from .serializers import RemapEventSerializer, RemapRequestSerializer


# ---- an action on schedules (``/schedules/{id}/remap/``: HEFT4K Algorithm 2) -----------------------------------
@ScheduleViewSet.extra_action
@extend_schema(request=RemapRequestSerializer, responses={202: JobSerializer})
@action(detail=True, methods=["post"])
def remap(self, request, pk=None):
    """Start a job that remaps the schedule without the failed nodes (partial or total, as Algorithm 2
    decides) and stores the new schedule; unless ``what_if``, it recreates only the pods that change."""
    schedule = self.get_object()
    serializer = RemapRequestSerializer(
        data=request.data, context={**self.get_serializer_context(), "schedule": schedule}
    )
    serializer.is_valid(raise_exception=True)
    job = start_job(Heft4kJob.REMAP, schedule.fleet, serializer.job_arguments(), request.user)
    return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)


class RemapEventViewSet(FleetScopedMixin, viewsets.ReadOnlyModelViewSet):
    """Every remap of a schedule: what Algorithm 2 decided, what moved, what changed in Kubernetes."""

    queryset = RemapEvent.objects.select_related("fleet")
    serializer_class = RemapEventSerializer
    filterset_fields = ["application", "schedule", "new_schedule", "trigger", "decision", "status"]
    ordering_fields = ["created", "elapsed_ms"]

    @extend_schema(request=None, responses={202: JobSerializer})
    @action(detail=True, methods=["post"])
    def apply(self, request, pk=None):
        """Start a job that applies a what-if remap: only the pods of its changed tasks are recreated."""
        event = self.get_object()
        reason = remapping.cannot_apply(event)
        if reason:
            return Response({"non_field_errors": [reason]}, status=status.HTTP_400_BAD_REQUEST)
        job = start_job(Heft4kJob.REMAP_APPLY, event.fleet, {"remap": event.pk}, request.user)
        return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)
