from drf_spectacular.utils import extend_schema
from rest_framework import status, viewsets
from rest_framework.decorators import action
from rest_framework.response import Response

from apps.tenancy.api import ExtensibleViewSetMixin, FleetScopedMixin
from apps.tenancy.bounds import SafeFormParser, SafeMultiPartParser

from .models import Application
from .serializers import (
    ApplicationGenerateSerializer,
    ApplicationImportResultSerializer,
    ApplicationImportSerializer,
    ApplicationListSerializer,
    ApplicationSerializer,
)


class ApplicationViewSet(FleetScopedMixin, ExtensibleViewSetMixin, viewsets.ModelViewSet):
    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"create", "update", "partial_update", "import_file"})
    # No docstring: it would become the description of every operation in the schema. Apps above workloads
    # add actions through ExtensibleViewSetMixin: ``schedule`` and ``compare`` (apps.scheduling.api).
    queryset = Application.objects.select_related("fleet")
    filterset_fields = ["fleet__slug", "source_format"]
    search_fields = ["name", "description"]
    ordering_fields = ["name", "created", "task_count"]

    def get_serializer_class(self):
        return ApplicationListSerializer if self.action == "list" else ApplicationSerializer

    @extend_schema(
        request={"multipart/form-data": ApplicationImportSerializer}, responses={201: ApplicationImportResultSerializer}
    )
    @action(detail=False, methods=["post"], url_path="import", parser_classes=[SafeMultiPartParser, SafeFormParser])
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
