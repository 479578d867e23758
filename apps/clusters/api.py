from drf_spectacular.utils import extend_schema
from rest_framework import status, viewsets
from rest_framework.decorators import action
from rest_framework.response import Response

from apps.clusters.kinds import ClusterJob
from apps.jobs.serializers import JobSerializer
from apps.jobs.services import start_job
from apps.tenancy.api import FleetScopedMixin

from .models import Cluster, ComputeNode, Link
from .serializers import ClusterImportSerializer, ClusterSerializer, ComputeNodeSerializer, LinkSerializer


class ClusterViewSet(FleetScopedMixin, viewsets.ModelViewSet):
    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"import_document"})
    queryset = Cluster.objects.select_related("fleet")
    serializer_class = ClusterSerializer
    filterset_fields = ["fleet__slug", "name"]
    search_fields = ["name", "description"]
    ordering_fields = ["name", "created"]

    @extend_schema(request=ClusterImportSerializer, responses={201: ClusterSerializer})
    @action(detail=False, methods=["post"], url_path="import")
    def import_document(self, request):
        """Create a cluster, its nodes and links from a ``continuum.cluster/v1`` document."""
        serializer = ClusterImportSerializer(data=request.data, context=self.get_serializer_context())
        serializer.is_valid(raise_exception=True)
        cluster = serializer.save()
        return Response(
            ClusterSerializer(cluster, context=self.get_serializer_context()).data, status=status.HTTP_201_CREATED
        )

    @extend_schema(request=None, responses={202: JobSerializer})
    @action(detail=True, methods=["post"])
    def sync(self, request, pk=None):
        """Start a job that reads the nodes (capacity, arch, Ready, taints) from the cluster's Kubernetes API."""
        cluster = self.get_object()
        job = start_job(ClusterJob.SYNC_CLUSTER, cluster.fleet, {"cluster": cluster.pk}, request.user)
        return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)


class ComputeNodeViewSet(FleetScopedMixin, viewsets.ModelViewSet):
    queryset = ComputeNode.objects.select_related("cluster")
    serializer_class = ComputeNodeSerializer
    fleet_lookup = "cluster__fleet"
    filterset_fields = ["cluster", "arch", "status", "rt", "criticality"]
    search_fields = ["name"]
    ordering_fields = ["name", "cpu", "memory_mib"]


class LinkViewSet(FleetScopedMixin, viewsets.ModelViewSet):
    queryset = Link.objects.select_related("cluster", "src", "dst")
    serializer_class = LinkSerializer
    fleet_lookup = "cluster__fleet"
    filterset_fields = ["cluster", "src", "dst"]
