"""REST API of assertion-based verification: assertions, monitors, handlers, violations and verdicts,
the robots' event endpoint, allocation runs (the MILP as a job) and migrations. Every queryset is scoped
to the caller's fleets (another fleet's object answers 404)."""

from django.db import transaction
from drf_spectacular.utils import extend_schema
from rest_framework import mixins, status, viewsets
from rest_framework.decorators import action
from rest_framework.response import Response

from apps.jobs.serializers import JobSerializer
from apps.jobs.services import start_job
from apps.tenancy.api import FleetScopedMixin, default_fleet
from apps.verification.kinds import VerificationJob

from . import services
from .models import AllocationRun, Assertion, Handler, MigrationEvent, Monitor, MonitorVerdict, Violation
from .serializers import (
    AllocationRequestSerializer,
    AllocationRunSerializer,
    AssertionSerializer,
    EventBatchSerializer,
    HandlerSerializer,
    HandlerSyncSerializer,
    MigrationEventSerializer,
    MonitorSerializer,
    MonitorVerdictSerializer,
    SimulationRequestSerializer,
    ViolationSerializer,
)


class AssertionViewSet(FleetScopedMixin, viewsets.ModelViewSet):
    """STL assertions (Fig. 3.40 grammar). A malformed one answers 400 naming the column."""

    queryset = Assertion.objects.select_related("fleet").prefetch_related("monitors")
    serializer_class = AssertionSerializer
    filterset_fields = ["name"]
    search_fields = ["name", "text", "description"]
    ordering_fields = ["name", "created"]


class MonitorViewSet(FleetScopedMixin, viewsets.ModelViewSet):
    """Monitors of assertions on a cluster; ``node`` is the node whose handler runs it."""

    queryset = Monitor.objects.select_related("fleet", "assertion", "cluster", "node")
    serializer_class = MonitorSerializer
    filterset_fields = ["assertion", "cluster", "node", "verdict", "tolerant"]
    search_fields = ["name"]
    ordering_fields = ["name", "violation_count", "events", "updated"]

    @extend_schema(request=None, responses={200: MonitorVerdictSerializer})
    @action(detail=True, methods=["post"])
    def finish(self, request, pk=None):
        """End the monitor's in-process stream: evaluate what is buffered and record its verdict."""
        row = services.finish_in_process(self.get_object())
        return Response(MonitorVerdictSerializer(row).data)


class HandlerViewSet(FleetScopedMixin, mixins.UpdateModelMixin, viewsets.ReadOnlyModelViewSet):
    """The monitor handler of each node (liveness, CPU statistics); threshold and delay are editable."""

    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"sync"})

    queryset = Handler.objects.select_related("node", "cluster")
    serializer_class = HandlerSerializer
    fleet_lookup = "cluster__fleet"
    filterset_fields = ["cluster", "is_coordinator"]
    robot_actions = {"sync"}  # a robot may refresh its handlers' reports (apps.tenancy.permissions)

    @extend_schema(request=HandlerSyncSerializer, responses={200: HandlerSerializer(many=True)})
    @action(detail=False, methods=["post"])
    def sync(self, request):
        """Create a handler per node of the cluster and read their reports, the coordinator and the
        monitors' verdicts from the cluster's verification network (Redis)."""
        ref = HandlerSyncSerializer(data=request.data, context=self.get_serializer_context())
        ref.is_valid(raise_exception=True)
        cluster = ref.validated_data["cluster"]
        with transaction.atomic():
            summary = services.sync_handlers(cluster)
        rows = self.get_queryset().filter(cluster=cluster)
        return Response({"summary": summary, "handlers": HandlerSerializer(rows, many=True).data})


class ViolationViewSet(FleetScopedMixin, viewsets.ReadOnlyModelViewSet):
    queryset = Violation.objects.select_related("monitor")
    serializer_class = ViolationSerializer
    fleet_lookup = "monitor__fleet"
    filterset_fields = ["monitor", "monitor__assertion", "monitor__cluster", "handler"]
    ordering_fields = ["time_ms", "created"]


class VerdictViewSet(FleetScopedMixin, viewsets.ReadOnlyModelViewSet):
    queryset = MonitorVerdict.objects.select_related("monitor")
    serializer_class = MonitorVerdictSerializer
    fleet_lookup = "monitor__fleet"
    filterset_fields = ["monitor", "verdict"]


class EventViewSet(viewsets.GenericViewSet):
    """Robots post events here, in batches; a malformed batch answers 400 and nothing of it is used."""

    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"create"})

    serializer_class = EventBatchSerializer
    robot_actions = {"create"}  # robots' tokens post events (apps.tenancy.permissions)
    throttle_scope = "reports"  # their own, high rate limit (REST_FRAMEWORK["DEFAULT_THROTTLE_RATES"])

    @extend_schema(request=EventBatchSerializer)
    def create(self, request):
        """With a handler of the cluster running, the batch goes to the handlers' Redis event stream (202);
        otherwise the cluster's monitors evaluate it here (200, with the violations found)."""
        batch = EventBatchSerializer(data=request.data, context={"request": request})
        batch.is_valid(raise_exception=True)
        data = batch.validated_data
        out = services.route_events(data["cluster"], data["events"], data.get("now"))
        code = status.HTTP_202_ACCEPTED if out["routed"] == "redis" else status.HTTP_200_OK
        return Response(out, status=code)


class AllocationRunViewSet(FleetScopedMixin, viewsets.ReadOnlyModelViewSet):
    """Runs of the monitor-allocation MILP: ``POST`` starts one as a job (with progress), ``simulate``
    runs a thesis case study and stores it as a series of runs."""

    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"create", "simulate"})

    queryset = AllocationRun.objects.select_related("fleet", "cluster").prefetch_related("migrations")
    serializer_class = AllocationRunSerializer
    filterset_fields = ["cluster", "source", "series", "status", "scenario"]
    ordering_fields = ["created", "t", "solve_time_ms"]

    @extend_schema(request=AllocationRequestSerializer, responses={202: JobSerializer})
    def create(self, request):
        req = AllocationRequestSerializer(data=request.data, context=self.get_serializer_context())
        req.is_valid(raise_exception=True)
        job = start_job(VerificationJob.ALLOCATE_MONITORS, req.fleet(request), req.job_arguments(), request.user)
        return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)

    @extend_schema(request=SimulationRequestSerializer, responses={202: JobSerializer})
    @action(detail=False, methods=["post"])
    def simulate(self, request):
        req = SimulationRequestSerializer(data=request.data)
        req.is_valid(raise_exception=True)
        fleet = default_fleet(request)
        job = start_job(VerificationJob.VERIFICATION_SIMULATION, fleet, req.job_arguments(), request.user)
        return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)


class MigrationEventViewSet(FleetScopedMixin, viewsets.ReadOnlyModelViewSet):
    queryset = MigrationEvent.objects.select_related("run")
    serializer_class = MigrationEventSerializer
    filterset_fields = ["run", "run__series", "monitor", "source", "target"]
    ordering_fields = ["t", "created"]
