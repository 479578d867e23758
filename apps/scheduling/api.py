from django.http import StreamingHttpResponse
from drf_spectacular.types import OpenApiTypes
from drf_spectacular.utils import OpenApiParameter, extend_schema
from rest_framework import mixins, serializers, status, viewsets
from rest_framework.decorators import action
from rest_framework.response import Response

from apps.jobs.serializers import JobSerializer
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from apps.tenancy.api import ExtensibleViewSetMixin, FleetScopedMixin
from apps.workloads.api import ApplicationViewSet

from . import reads
from .models import Comparison, Schedule
from .serializers import (
    AssignmentFilterSerializer,
    AssignmentSerializer,
    CompareRequestSerializer,
    ComparisonListSerializer,
    ComparisonSerializer,
    ScheduleListSerializer,
    ScheduleRequestSerializer,
    ScheduleSerializer,
)

#: What ``?search=`` looks in, on the API and on the list pages alike (issue 30: it was silently ignored).
SCHEDULE_SEARCH = ["application__name", "algorithm", "cluster__name"]
COMPARISON_SEARCH = ["application__name", "cluster__name", "best"]


class ScheduleViewSet(
    FleetScopedMixin, ExtensibleViewSetMixin, mixins.DestroyModelMixin, viewsets.ReadOnlyModelViewSet
):
    """Stored schedules (created by scheduling jobs) and their push to Kubernetes."""

    # Apps above scheduling add actions through ExtensibleViewSetMixin: ``remap`` (apps.heft4k.api).

    queryset = Schedule.objects.select_related("fleet")
    filterset_fields = ["application", "cluster", "algorithm"]
    search_fields = SCHEDULE_SEARCH
    ordering_fields = ["created", "makespan"]

    def get_serializer_class(self):
        if self.action == "list":
            return ScheduleListSerializer
        return AssignmentSerializer if self.action == "assignments" else ScheduleSerializer

    @extend_schema(
        parameters=[
            OpenApiParameter(
                name,
                {"type": "integer", "minimum": field.min_value, "maximum": field.max_value}
                if isinstance(field, serializers.IntegerField)
                else str,
                enum=list(field.choices) if isinstance(field, serializers.ChoiceField) else None,
                description=str(field.help_text),
            )
            for name, field in AssignmentFilterSerializer().fields.items()
        ]
        + [
            OpenApiParameter(
                "cursor",
                str,
                description="keyset pages: empty for the first, then the cursor of the answer's next link; "
                "the answer is {next, results} (no count), each page as cheap as the first",
            )
        ],
        responses={200: AssignmentSerializer(many=True)},
        filters=False,
    )
    @action(detail=True, methods=["get"], filter_backends=[])
    def assignments(self, request, pk=None):
        """The schedule's assignments, paginated (``limit``, ``offset``) in start order, filtered by part of the
        task's id (``task``), the processor (``processor``), the frame (``frame``) or the placement status
        (``placement``); a malformed filter or a processor not in the schedule is a 400 naming it."""
        schedule = self.get_object()
        processors = [p.get("id") for p in schedule.platform.get("processors", []) if isinstance(p, dict)]
        processors += schedule.assignments.order_by().values_list("processor", flat=True).distinct()
        context = {**self.get_serializer_context(), "processors": set(processors)}
        filters = AssignmentFilterSerializer(data=request.query_params, context=context)
        filters.is_valid(raise_exception=True)
        cursor = request.query_params.get("cursor")
        if cursor is not None:
            return self._keyset(request, filters.filter(schedule.assignments.all()), cursor)
        page = self.paginate_queryset(filters.filter(schedule.assignments.all()))
        data = AssignmentSerializer(page, many=True, context=self.get_serializer_context()).data
        return self.get_paginated_response(data)

    def _keyset(self, request, queryset, cursor: str) -> Response:
        limit = self.paginator.get_limit(request)  # the same bounded ``limit`` as the offset pages
        try:
            rows, after = reads.keyset_page(queryset, cursor, limit)
        except reads.BadCursor as exc:
            return Response({"cursor": [str(exc)]}, status=status.HTTP_400_BAD_REQUEST)
        following = None
        if after is not None:
            params = request.query_params.copy()
            params["cursor"] = after
            following = request.build_absolute_uri(f"{request.path}?{params.urlencode()}")
        data = AssignmentSerializer(rows, many=True, context=self.get_serializer_context()).data
        return Response({"next": following, "results": data})

    @extend_schema(
        parameters=[OpenApiParameter("as", str, enum=["csv", "jsonl"], description="CSV (default) or JSON lines")],
        responses={(200, "text/csv"): OpenApiTypes.STR, (200, "application/jsonl"): OpenApiTypes.STR},
    )
    @action(detail=True, methods=["get"], filter_backends=[], pagination_class=None)
    def export(self, request, pk=None):
        """Every assignment of the schedule in one streamed answer, in start order: CSV with a header
        (``as=csv``, the default) or one JSON object a line (``as=jsonl``)."""
        schedule = self.get_object()
        kind = request.query_params.get("as", "csv")
        if kind not in ("csv", "jsonl"):
            return Response({"as": ["must be csv or jsonl"]}, status=status.HTTP_400_BAD_REQUEST)
        body = reads.export_csv(schedule.pk) if kind == "csv" else reads.export_jsonl(schedule.pk)
        media = "text/csv; charset=utf-8" if kind == "csv" else "application/jsonl; charset=utf-8"
        response = StreamingHttpResponse(body, content_type=media)
        response["Content-Disposition"] = f'attachment; filename="schedule-{schedule.pk}.{kind}"'
        return response

    @extend_schema(request=None, responses={202: JobSerializer})
    @action(detail=True, methods=["post"])
    def push(self, request, pk=None):
        """Start a job that creates one pod per task in the cluster's Kubernetes API, bound to its node."""
        schedule = self.get_object()
        if schedule.cluster is None or not schedule.cluster.kubeconfig:
            return Response(
                {"cluster": ["this schedule's cluster has no Kubernetes API configured"]},
                status=status.HTTP_400_BAD_REQUEST,
            )
        job = start_job(SchedulingJob.PUSH_SCHEDULE, schedule.fleet, {"schedule": schedule.pk}, request.user)
        return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)


class ComparisonViewSet(FleetScopedMixin, mixins.DestroyModelMixin, viewsets.ReadOnlyModelViewSet):
    """Comparisons of several algorithms on one application (created by ``compare`` jobs); deleting one
    deletes the schedules it made."""

    queryset = Comparison.objects.select_related("fleet")
    filterset_fields = ["application", "cluster", "best"]
    search_fields = COMPARISON_SEARCH
    ordering_fields = ["created"]

    def get_queryset(self):
        qs = super().get_queryset()
        return qs.prefetch_related("schedules") if self.action == "retrieve" else qs

    def get_serializer_class(self):
        return ComparisonListSerializer if self.action == "list" else ComparisonSerializer


# ---- actions on applications (``/applications/{id}/schedule/`` and ``/compare/``) ----------------------------
def _request_context(viewset, app) -> dict:
    """The context of the schedule and compare request contracts (apps/scheduling/serializers.py)."""
    return {**viewset.get_serializer_context(), "application": app}


@ApplicationViewSet.extra_action
@extend_schema(request=ScheduleRequestSerializer, responses={202: JobSerializer})
@action(detail=True, methods=["post"])
def schedule(self, request, pk=None):
    """Start a scheduling job; its result links to the stored schedule."""
    app = self.get_object()
    serializer = ScheduleRequestSerializer(data=request.data, context=_request_context(self, app))
    serializer.is_valid(raise_exception=True)
    job = start_job(SchedulingJob.SCHEDULE, app.fleet, serializer.job_arguments(), request.user)
    return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)


@ApplicationViewSet.extra_action
@extend_schema(request=CompareRequestSerializer, responses={202: JobSerializer})
@action(detail=True, methods=["post"])
def compare(self, request, pk=None):
    """Start a job that runs several algorithms on this application and target (frames optional) and stores
    each schedule plus a comparison (makespan, SLR, speedup vs VisionWorks, overlap, idle time)."""
    app = self.get_object()
    serializer = CompareRequestSerializer(data=request.data, context=_request_context(self, app))
    serializer.is_valid(raise_exception=True)
    job = start_job(SchedulingJob.COMPARE, app.fleet, serializer.job_arguments(), request.user)
    return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)
