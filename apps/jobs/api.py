from rest_framework import viewsets

from apps.tenancy.api import FleetScopedMixin

from .models import Job
from .serializers import JobSerializer


class JobViewSet(FleetScopedMixin, viewsets.ReadOnlyModelViewSet):
    """Every long operation with its state and progress (0-100 and a message)."""

    queryset = Job.objects.select_related("fleet", "created_by")
    serializer_class = JobSerializer
    filterset_fields = ["state", "kind", "fleet__slug"]
    ordering_fields = ["created", "finished"]
