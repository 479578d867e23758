from drf_spectacular.utils import OpenApiResponse, extend_schema
from rest_framework import status, viewsets
from rest_framework.decorators import action
from rest_framework.response import Response

from apps.tenancy.api import FleetScopedMixin

from .liveness import recover_lost_jobs
from .models import Job
from .search import search_jobs
from .serializers import JobDetailSerializer, JobSerializer
from .services import JobActionRefused, cancel_job, retry_job

REFUSED = OpenApiResponse(description="the job cannot be cancelled / retried as it is: `detail` says why")


class JobViewSet(FleetScopedMixin, viewsets.ReadOnlyModelViewSet):
    """Every long operation with its state and progress (0-100 and a message); one job also with its log.

    A running job whose worker is gone is queued again (or failed) before it is shown, so a reader never
    waits on a run that cannot end (apps/jobs/liveness.py). ``POST {id}/cancel/`` stops a job (a queued one at
    once, a running one at its next step); ``POST {id}/retry/`` runs a failed or cancelled job again as a new
    job with the same arguments.
    """

    queryset = Job.objects.select_related("fleet", "created_by")
    serializer_class = JobSerializer
    filterset_fields = ["state", "kind", "fleet__slug"]
    ordering_fields = ["created", "finished"]

    def filter_queryset(self, queryset):
        """The filters, then ``?search=`` as the jobs list page does (apps/jobs/search.py): kind, state,
        message, algorithm, and the names of the application or cluster a job works on."""
        queryset = super().filter_queryset(queryset)
        return search_jobs(queryset, self.request.query_params.get("search", "").strip()[:100])

    def get_serializer_class(self):
        return JobDetailSerializer if self.action in ("retrieve", "cancel", "retry") else JobSerializer

    def list(self, request, *args, **kwargs):
        recover_lost_jobs(self.get_queryset())
        return super().list(request, *args, **kwargs)

    def retrieve(self, request, *args, **kwargs):
        job = self.get_object()
        if recover_lost_jobs(Job.objects.filter(pk=job.pk)):
            job.refresh_from_db()
        return Response(self.get_serializer(job).data)

    @extend_schema(request=None, responses={200: JobDetailSerializer, 409: REFUSED})
    @action(detail=True, methods=["post"])
    def cancel(self, request, pk=None):
        """Cancel the job: 200 with the job (``cancelled``, or ``cancel_requested`` while its run reaches its
        next step); 409 when it has ended or is already being cancelled."""
        try:
            job = cancel_job(self.get_object(), request.user)
        except JobActionRefused as exc:
            return Response({"detail": str(exc)}, status=status.HTTP_409_CONFLICT)
        return Response(self.get_serializer(job).data)

    @extend_schema(request=None, responses={202: JobDetailSerializer, 409: REFUSED})
    @action(detail=True, methods=["post"])
    def retry(self, request, pk=None):
        """Run a failed or cancelled job again: 202 with the new job (same kind, fleet and arguments,
        ``retry_of`` the old one); 409 for a job that is running, queued or succeeded."""
        try:
            job = retry_job(self.get_object(), request.user)
        except JobActionRefused as exc:
            return Response({"detail": str(exc)}, status=status.HTTP_409_CONFLICT)
        return Response(self.get_serializer(job).data, status=status.HTTP_202_ACCEPTED)
