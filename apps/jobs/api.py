from rest_framework import viewsets
from rest_framework.response import Response

from apps.tenancy.api import FleetScopedMixin

from .liveness import recover_lost_jobs
from .models import Job
from .serializers import JobSerializer


class JobViewSet(FleetScopedMixin, viewsets.ReadOnlyModelViewSet):
    """Every long operation with its state and progress (0-100 and a message).

    A running job whose worker is gone is queued again (or failed) before it is shown, so a reader never
    waits on a run that cannot end (apps/jobs/liveness.py; the quick start runs no beat that would).
    """

    queryset = Job.objects.select_related("fleet", "created_by")
    serializer_class = JobSerializer
    filterset_fields = ["state", "kind", "fleet__slug"]
    ordering_fields = ["created", "finished"]

    def list(self, request, *args, **kwargs):
        recover_lost_jobs(self.get_queryset())
        return super().list(request, *args, **kwargs)

    def retrieve(self, request, *args, **kwargs):
        job = self.get_object()
        if recover_lost_jobs(Job.objects.filter(pk=job.pk)):
            job.refresh_from_db()
        return Response(self.get_serializer(job).data)
