"""REST API: ROS graphs (import, edit, cluster), clusterings (read-outs, Dockerfiles, place) and placements
(plan, the "why" table per container, push to Kubernetes). Actions that compute start jobs (202 + the job)."""

from django.http import HttpResponse
from drf_spectacular.types import OpenApiTypes
from drf_spectacular.utils import OpenApiParameter, extend_schema
from rest_framework import mixins, serializers, status, viewsets
from rest_framework.decorators import action
from rest_framework.exceptions import NotFound, ValidationError
from rest_framework.response import Response

from apps.containers.kinds import ContainersJob
from apps.jobs.serializers import JobSerializer
from apps.jobs.services import start_job
from apps.tenancy.api import FleetScopedMixin, ScopedSerializer
from apps.tenancy.bounds import SafeFormParser, SafeMultiPartParser
from continuum.engine.core.errors import InputError

from . import services
from .models import Clustering, Placement, RosGraph
from .serializers import (
    ClusteringListSerializer,
    ClusteringSerializer,
    ClusterRequestSerializer,
    PlacementListSerializer,
    PlacementSerializer,
    PlaceRequestSerializer,
    RosGraphImportSerializer,
    RosGraphListSerializer,
    RosGraphSerializer,
)


def job_response(view, job) -> Response:
    return Response(JobSerializer(job, context=view.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)


class RosGraphViewSet(
    FleetScopedMixin,
    mixins.ListModelMixin,
    mixins.RetrieveModelMixin,
    mixins.UpdateModelMixin,
    mixins.DestroyModelMixin,
    viewsets.GenericViewSet,
):
    """ROS computation graphs. Create them with ``import``; PATCH edits levels, rates and message sizes."""

    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"import_file", "update", "partial_update"})

    queryset = RosGraph.objects.select_related("fleet")
    filterset_fields = ["fleet__slug", "source_format"]
    search_fields = ["name", "description"]
    ordering_fields = ["name", "created", "node_count"]

    def get_serializer_class(self):
        return RosGraphListSerializer if self.action == "list" else RosGraphSerializer

    @extend_schema(request={"multipart/form-data": RosGraphImportSerializer}, responses={201: RosGraphSerializer})
    @action(detail=False, methods=["post"], url_path="import", parser_classes=[SafeMultiPartParser, SafeFormParser])
    def import_file(self, request):
        """Create a ROS graph from an uploaded file (contract JSON, Autoware JSON, iRobot topology, .dot)."""
        serializer = RosGraphImportSerializer(data=request.data, context=self.get_serializer_context())
        serializer.is_valid(raise_exception=True)
        row = serializer.save()
        return Response(RosGraphSerializer(row, context=self.get_serializer_context()).data, status=201)

    @extend_schema(request=ClusterRequestSerializer, responses={202: JobSerializer})
    @action(detail=True, methods=["post"])
    def cluster(self, request, pk=None):
        """Start a job that groups the ROS nodes into containers and plans their images."""
        rosgraph = self.get_object()
        serializer = ClusterRequestSerializer(data=request.data, context=self.get_serializer_context())
        serializer.is_valid(raise_exception=True)
        return job_response(
            self, start_job(ContainersJob.CLUSTER_ROS, rosgraph.fleet, serializer.job_arguments(rosgraph), request.user)
        )


class BuildImagesRequestSerializer(ScopedSerializer):
    export = serializers.BooleanField(
        required=False, default=False, help_text="also write docker-archives for scripts/cluster import-image"
    )


class ClusteringViewSet(FleetScopedMixin, mixins.DestroyModelMixin, viewsets.ReadOnlyModelViewSet):
    """Results of clustering jobs: containers with their ROS nodes, bandwidth, image plan and disk figures."""

    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"place"})

    queryset = Clustering.objects.select_related("fleet", "rosgraph")
    filterset_fields = ["rosgraph", "fleet__slug"]
    ordering_fields = ["created", "inter_container_bandwidth", "container_count"]

    def get_serializer_class(self):
        return ClusteringListSerializer if self.action == "list" else ClusteringSerializer

    @extend_schema(
        parameters=[OpenApiParameter("archive", str, enum=list(services.ARCHIVES), default="tar.gz")],
        responses={(200, "application/gzip"): OpenApiTypes.BINARY, (200, "application/zip"): OpenApiTypes.BINARY},
    )
    @action(detail=True, methods=["get"])
    def dockerfiles(self, request, pk=None):
        """The Dockerfiles (one directory per image), ``build.sh`` and ``plan.json`` as tar.gz or zip."""
        clustering = self.get_object()
        kind = request.query_params.get("archive", "tar.gz")
        if kind not in services.ARCHIVES:
            return Response({"archive": [f"one of {', '.join(services.ARCHIVES)}"]}, status=400)
        if not clustering.images:
            raise NotFound("this clustering has no image plan: its ROS nodes list no packages")
        try:
            data, content_type, filename = services.dockerfiles_archive(clustering, kind)
        except InputError as exc:  # stored before names were checked: refuse to write it into a build script
            return Response({exc.field or "archive": [str(exc)]}, status=409)
        response = HttpResponse(data, content_type=content_type)
        response["Content-Disposition"] = f'attachment; filename="{filename}"'
        return response

    @extend_schema(request=PlaceRequestSerializer, responses={202: JobSerializer})
    @action(detail=True, methods=["post"])
    def place(self, request, pk=None):
        """Start a job that places this clustering's containers on a cluster's nodes."""
        clustering = self.get_object()
        data = request.data.copy() if hasattr(request.data, "copy") else dict(request.data)
        data["clustering"] = clustering.pk
        serializer = PlaceRequestSerializer(data=data, context=self.get_serializer_context())
        serializer.is_valid(raise_exception=True)
        job = start_job(ContainersJob.PLACE, clustering.fleet, serializer.job_arguments(), request.user)
        return job_response(self, job)

    @extend_schema(request=BuildImagesRequestSerializer, responses={202: JobSerializer})
    @action(detail=True, methods=["post"], url_path="build-images")
    def build_images(self, request, pk=None):
        """Start a job that builds this clustering's images by inheritance with buildah (Debian packages, on the
        worker's machine) and measures their layers next to the planner's prediction (Table 4.16 from images)."""
        clustering = self.get_object()
        serializer = BuildImagesRequestSerializer(data=request.data)
        serializer.is_valid(raise_exception=True)
        if not clustering.images:
            raise ValidationError({"clustering": ["its ROS nodes list no packages: no image plan to build"]})
        arguments = {"clustering": clustering.pk, "export": serializer.validated_data.get("export", False)}
        job = start_job(ContainersJob.BUILD_IMAGES, clustering.fleet, arguments, request.user)
        return job_response(self, job)


class PlacementViewSet(FleetScopedMixin, mixins.DestroyModelMixin, viewsets.ReadOnlyModelViewSet):
    """Placements of containers on nodes, every node's verdict for every container, and their push."""

    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"run"})

    queryset = Placement.objects.select_related("fleet", "cluster", "rosgraph")
    filterset_fields = ["clustering", "cluster", "policy", "rosgraph"]
    ordering_fields = ["created", "inter_node_bandwidth"]

    def get_queryset(self):
        qs = super().get_queryset()
        return qs.prefetch_related("deployments") if self.action == "retrieve" else qs

    def get_serializer_class(self):
        return PlacementListSerializer if self.action == "list" else PlacementSerializer

    @extend_schema(request=PlaceRequestSerializer, responses={202: JobSerializer})
    @action(detail=False, methods=["post"])
    def run(self, request):
        """Start a placement job for a clustering or a ``continuum.containers/v1`` document."""
        serializer = PlaceRequestSerializer(data=request.data, context=self.get_serializer_context())
        serializer.is_valid(raise_exception=True)
        job = start_job(ContainersJob.PLACE, serializer.fleet(), serializer.job_arguments(), request.user)
        return job_response(self, job)

    @extend_schema(
        parameters=[
            OpenApiParameter("container", str, description="one container (default: every container)"),
            OpenApiParameter(
                "full", bool, description="with container: every node's verdict, recomputed from the stored inputs"
            ),
        ],
        responses={200: OpenApiTypes.OBJECT},
    )
    @action(detail=True, methods=["get"])
    def why(self, request, pk=None):
        """Why each container went where it went: per node, the rejecting filter and reason, or each
        scoring policy's score and the total (like kube-scheduler-simulator). Stored bounded (the best
        candidates, nodes per filter in ``rejections``, an example each); ``container`` with ``full=1``:
        every node's verdict, recomputed from the placement's stored inputs."""
        placement = self.get_object()
        plan = placement.engine_plan()
        container = request.query_params.get("container")
        if container is not None:
            try:
                full = request.query_params.get("full", "").lower() in ("1", "true", "yes")
                return Response(services.why_table(plan, container, placement, full=full))
            except KeyError:
                raise NotFound(f"placement {placement.pk} has no container {container!r}") from None
        tables = [services.why_table(plan, d.item) for d in plan.decisions]
        return Response({"policy": placement.policy, "containers": tables})

    @extend_schema(request=None, responses={202: JobSerializer})
    @action(detail=True, methods=["post"])
    def push(self, request, pk=None):
        """Start a job that creates or updates one Deployment per container, pinned to its node."""
        placement = self.get_object()
        if placement.cluster is None or not placement.cluster.kubeconfig:
            return Response(
                {"cluster": ["this placement's cluster has no Kubernetes API configured"]},
                status=status.HTTP_400_BAD_REQUEST,
            )
        return job_response(
            self, start_job(ContainersJob.PUSH_PLACEMENT, placement.fleet, {"placement": placement.pk}, request.user)
        )
