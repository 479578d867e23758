from drf_spectacular.utils import extend_schema
from rest_framework import status, viewsets
from rest_framework.decorators import action
from rest_framework.response import Response

from apps.jobs.serializers import JobSerializer
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.serializers import CompareRequestSerializer, ScheduleRequestSerializer
from apps.tenancy.api import FleetScopedMixin
from apps.tenancy.bounds import SafeFormParser, SafeMultiPartParser

from .models import Application
from .serializers import (
    ApplicationGenerateSerializer,
    ApplicationImportResultSerializer,
    ApplicationImportSerializer,
    ApplicationListSerializer,
    ApplicationSerializer,
)


class ApplicationViewSet(FleetScopedMixin, viewsets.ModelViewSet):
    queryset = Application.objects.select_related("fleet")
    filterset_fields = ["fleet__slug", "source_format"]
    search_fields = ["name", "description"]
    ordering_fields = ["name", "created", "task_count"]

    def get_serializer_class(self):
        return ApplicationListSerializer if self.action == "list" else ApplicationSerializer

    @extend_schema(
        request={"multipart/form-data": ApplicationImportSerializer}, responses={201: ApplicationImportResultSerializer}
    )
    @action(
        detail=False, methods=["post"], url_path="import", parser_classes=[SafeMultiPartParser, SafeFormParser]
    )
    def import_file(self, request):
        """Create an application from an uploaded DAG file: continuum JSON, WfCommons WfFormat 1.5, Pegasus DAX,
        Kasahara STG (reader ``options`` such as ``{"ccr": 1, "processors": 4, "heterogeneity": 0.5}``) or the
        thesis simulator's CSV. The format is ``format``, else the file extension's, else guessed."""
        serializer = ApplicationImportSerializer(data=request.data, context=self.get_serializer_context())
        serializer.is_valid(raise_exception=True)
        app = serializer.save()
        app.warnings = serializer.validated_data["warnings"]
        return Response(
            ApplicationImportResultSerializer(app, context=self.get_serializer_context()).data,
            status=status.HTTP_201_CREATED,
        )

    @extend_schema(request=ApplicationGenerateSerializer, responses={201: ApplicationSerializer})
    @action(detail=False, methods=["post"])
    def generate(self, request):
        """Create an application from a seeded synthetic DAG (``thesis`` Tree/Linear or ``layered``)."""
        serializer = ApplicationGenerateSerializer(data=request.data, context=self.get_serializer_context())
        serializer.is_valid(raise_exception=True)
        app = serializer.save()
        return Response(
            ApplicationSerializer(app, context=self.get_serializer_context()).data, status=status.HTTP_201_CREATED
        )

    @extend_schema(request=ScheduleRequestSerializer, responses={202: JobSerializer})
    @action(detail=True, methods=["post"])
    def schedule(self, request, pk=None):
        """Start a scheduling job; its result links to the stored schedule."""
        app = self.get_object()
        serializer = ScheduleRequestSerializer(data=request.data, context=self._request_context(app))
        serializer.is_valid(raise_exception=True)
        job = start_job(SchedulingJob.SCHEDULE, app.fleet, serializer.job_arguments(), request.user)
        return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)

    @extend_schema(request=CompareRequestSerializer, responses={202: JobSerializer})
    @action(detail=True, methods=["post"])
    def compare(self, request, pk=None):
        """Start a job that runs several algorithms on this application and target (frames optional) and stores
        each schedule plus a comparison (makespan, SLR, speedup vs VisionWorks, overlap, idle time)."""
        app = self.get_object()
        serializer = CompareRequestSerializer(data=request.data, context=self._request_context(app))
        serializer.is_valid(raise_exception=True)
        job = start_job(SchedulingJob.COMPARE, app.fleet, serializer.job_arguments(), request.user)
        return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)

    def _request_context(self, app: Application) -> dict:
        """The context of the schedule and compare request contracts (apps/scheduling/serializers.py)."""
        return {**self.get_serializer_context(), "application": app}
