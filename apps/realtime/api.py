"""RT-Kube's REST API (spec 03 16.1): RealTime objects, policies, the monitoring endpoint, what the
scheduler and the monitor did. Every queryset is limited to the caller's fleets (via the cluster)."""

from __future__ import annotations

from django.core.exceptions import ValidationError as DjangoValidationError
from django.db import transaction
from django.http import HttpResponse
from django.utils import timezone
from drf_spectacular.utils import OpenApiParameter, extend_schema
from rest_framework import mixins, status, viewsets
from rest_framework.decorators import action
from rest_framework.exceptions import ValidationError
from rest_framework.generics import get_object_or_404
from rest_framework.response import Response

from apps.clusters.models import Cluster, ComputeNode
from apps.jobs.serializers import JobSerializer
from apps.jobs.services import start_job
from apps.realtime.kinds import RealtimeJob
from apps.tenancy.api import FleetScopedMixin
from apps.tenancy.models import FleetToken
from apps.tenancy.scoping import visible_fleets
from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import load_yaml_all
from continuum.engine.rtkube.rt_model import REALTIME_KIND, realtime_from_yaml, realtime_to_yaml, rtset_from_dict

from . import monitoring, planning
from .kube import has_api
from .models import (
    Monitoring,
    MonitoringReport,
    NodeTaint,
    RealTime,
    RealTimeWcet,
    RTDecision,
    RTEvent,
    RTPlan,
    RTPod,
    RTPolicy,
)
from .serializers import (
    AdmissionReportSerializer,
    ClusterRefSerializer,
    MonitoringReportSerializer,
    MonitoringSerializer,
    NodeAdmissionSerializer,
    NodeTaintSerializer,
    RealTimeImportSerializer,
    RealTimeSerializer,
    ReportBatchSerializer,
    RTDecisionSerializer,
    RTEventSerializer,
    RTPlanSerializer,
    RTPodSerializer,
    RTPolicySerializer,
    WhatIfSerializer,
    WhyNotQuerySerializer,
    WhyNotSerializer,
)
from .tasks import queue_reconcile


class ClusterScoped(FleetScopedMixin):
    fleet_lookup = "cluster__fleet"


def _visible_cluster(request, pk, with_nodes: bool = False) -> Cluster:
    try:
        auth = getattr(request, "auth", None)
        # A fleet token (every robot's report) names its one fleet: no subquery to compile and run.
        scope = {"fleet_id": auth.fleet_id} if isinstance(auth, FleetToken) else {"fleet__in": visible_fleets(request)}
        clusters = Cluster.objects.select_related("rt_policy")
        if with_nodes:  # the report endpoint: its nodes in the same round trip
            clusters = monitoring.with_node_ids(clusters)
        return clusters.get(pk=int(pk), **scope)
    except (Cluster.DoesNotExist, TypeError, ValueError) as exc:
        raise ValidationError({"cluster": [f"no cluster {pk!r} among your fleets' clusters"]}) from exc


class RealTimeViewSet(ClusterScoped, viewsets.ModelViewSet):
    """RealTime objects (Listing 3.33). Saving one writes it to the cluster's Kubernetes API as well."""

    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"import_yaml", "sync"})

    queryset = RealTime.objects.select_related("cluster").prefetch_related("wcets__node")
    serializer_class = RealTimeSerializer
    filterset_fields = ["cluster", "namespace", "criticality", "sync_state"]
    search_fields = ["name"]
    ordering_fields = ["name", "criticality", "period", "created"]

    def perform_create(self, serializer):
        row = serializer.save()
        if has_api(row.cluster):
            push_in_job([row], self.request.user)

    perform_update = perform_create

    @extend_schema(responses={204: None, 202: JobSerializer})
    def destroy(self, request, *args, **kwargs):
        """Delete the row; with a Kubernetes API, its object there first (a job: 202 with the job when a worker
        runs it, 204 once done, 400 with the reason when the API refused and the row stays)."""
        instance = self.get_object()
        if not (has_api(instance.cluster) and instance.uid):
            instance.delete()
            return Response(status=status.HTTP_204_NO_CONTENT)
        job = start_job(RealtimeJob.RT_DELETE, instance.cluster.fleet, {"realtime": instance.pk}, request.user)
        if job.state == job.State.SUCCEEDED:
            return Response(status=status.HTTP_204_NO_CONTENT)
        if job.state == job.State.FAILED:
            raise ValidationError({"non_field_errors": [job.error]})
        return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)

    @extend_schema(responses={(200, "application/yaml"): str})
    @action(detail=True, methods=["get"])
    def yaml(self, request, pk=None):
        """The object as Listing 3.33 writes it."""
        return HttpResponse(self.get_object().to_yaml(), content_type="application/yaml")

    @extend_schema(
        parameters=[OpenApiParameter("cluster", int, required=True)], responses={(200, "application/yaml"): str}
    )
    @action(detail=False, methods=["get"])
    def export(self, request):
        """Every RealTime object of a cluster as one YAML stream."""
        cluster = _visible_cluster(request, request.query_params.get("cluster"))
        rows = self.get_queryset().filter(cluster=cluster)
        text = realtime_to_yaml([r.to_engine() for r in rows]) if rows else ""
        return HttpResponse(text, content_type="application/yaml")

    @extend_schema(request=RealTimeImportSerializer, responses={201: RealTimeSerializer(many=True)})
    @action(detail=False, methods=["post"], url_path="import")
    def import_yaml(self, request):
        """Create (or replace) RealTime objects from YAML; all or nothing."""
        s = RealTimeImportSerializer(data=request.data, context=self.get_serializer_context())
        s.is_valid(raise_exception=True)
        cluster = s.validated_data["cluster"]
        rows = import_realtimes(cluster, s.validated_data["yaml"], s.validated_data.get("namespace"))
        if has_api(cluster) and rows:
            push_in_job(rows, request.user)
        return Response(
            RealTimeSerializer(rows, many=True, context=self.get_serializer_context()).data,
            status=status.HTTP_201_CREATED,
        )

    @extend_schema(request=ClusterRefSerializer, responses={202: JobSerializer})
    @action(detail=False, methods=["post"])
    def sync(self, request):
        """Start a job: install the CRDs, mirror node RT attributes, RealTime objects and Monitoring counters."""
        s = ClusterRefSerializer(data=request.data, context=self.get_serializer_context())
        s.is_valid(raise_exception=True)
        cluster = s.validated_data["cluster"]
        if not has_api(cluster):
            raise ValidationError({"cluster": [f"cluster {cluster.name!r} has no kubeconfig: nothing to sync with"]})
        args = {"cluster": cluster.pk}
        if s.validated_data.get("namespace"):
            args["namespace"] = s.validated_data["namespace"]
        job = start_job(RealtimeJob.RT_SYNC, cluster.fleet, args, request.user)
        return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)


def push_in_job(rows: list[RealTime], user=None):
    """Write the rows to their cluster's Kubernetes API in an ``rt_push`` job: no Kubernetes call in the web
    request. Without a broker the job runs at once and the rows show its outcome; with one they show it once
    the worker is done (``sync_state``, and the job)."""
    job = start_job(RealtimeJob.RT_PUSH, rows[0].cluster.fleet, {"realtimes": [r.pk for r in rows]}, user)
    fresh = {
        r.pk: r
        for r in RealTime.objects.filter(pk__in=[r.pk for r in rows]).only(
            "uid", "resource_version", "dirty", "sync_state", "sync_error"
        )
    }
    for row in rows:
        if row.pk in fresh:
            for field in ("uid", "resource_version", "dirty", "sync_state", "sync_error"):
                setattr(row, field, getattr(fresh[row.pk], field))
    return job


def import_realtimes(cluster: Cluster, text: str, namespace: str | None = None) -> list[RealTime]:
    """Rows from a YAML stream of RealTime objects (validated by the engine); InputError names the culprit."""
    nodes = {n.name: n for n in cluster.nodes.all()}
    containers = realtime_from_yaml(text, nodes)
    # The engine validated the stream; read the namespaces it does not model.
    docs = [d for d in load_yaml_all(text, "yaml") if isinstance(d, dict) and d.get("kind") == REALTIME_KIND]
    rows = []
    with transaction.atomic():
        for c, doc in zip(containers, docs, strict=True):
            ns = (doc.get("metadata") or {}).get("namespace") or namespace or cluster.namespace
            row = RealTime.objects.filter(cluster=cluster, namespace=ns, name=c.name).first() or RealTime(
                cluster=cluster, namespace=ns, name=c.name
            )
            row.criticality, row.period, row.deadline = c.criticality, c.period, c.deadline
            row.stateless, row.cpu, row.memory_mib = c.stateless, c.cpu, c.memory_mib
            row.dirty = True
            try:
                row.full_clean(exclude=["cluster", "uid", "resource_version", "sync_error"], validate_unique=False)
            except DjangoValidationError as exc:
                raise ValidationError({k: [f"{c.name}: {m}" for m in v] for k, v in exc.message_dict.items()}) from exc
            row.save()
            row.wcets.all().delete()
            RealTimeWcet.objects.bulk_create(
                RealTimeWcet(realtime=row, node=nodes[n], wcet=w, position=i) for i, (n, w) in enumerate(c.wcet.items())
            )
            rows.append(row)
    return rows


class RTPolicyViewSet(ClusterScoped, mixins.CreateModelMixin, mixins.UpdateModelMixin, viewsets.ReadOnlyModelViewSet):
    """Per cluster: thresholds and victim policy of the monitor, Eq. 3.18's parameters of the scheduler."""

    queryset = RTPolicy.objects.select_related("cluster")
    serializer_class = RTPolicySerializer
    filterset_fields = ["cluster"]


class MonitoringViewSet(ClusterScoped, viewsets.ReadOnlyModelViewSet):
    """The latest counters of each monitored container (Listing 3.37)."""

    queryset = Monitoring.objects.select_related("node")
    serializer_class = MonitoringSerializer
    filterset_fields = ["cluster", "node__name", "container_name"]


class MonitoringReportViewSet(ClusterScoped, mixins.CreateModelMixin, viewsets.ReadOnlyModelViewSet):
    """Missed-deadline reports. POST a batch: ``{"cluster": id, "reports": [Monitoring objects or specs]}``.

    Each report is stored, and reconciled when it exceeds the cluster's thresholds (eviction and node taint,
    thesis 3.4). On a model-only cluster the answer lists what the monitor did; with a Kubernetes API the
    violations are stored and handed to the ``rt_reconcile`` task (``queued``), whose events are in
    ``/api/v1/rt-events/``. A malformed report rejects the whole batch (400).
    """

    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"create"})

    queryset = MonitoringReport.objects.all()
    serializer_class = MonitoringReportSerializer
    robot_actions = {"create"}  # robots' tokens post reports (apps.tenancy.permissions)
    throttle_scope = "reports"  # their own, high rate limit (REST_FRAMEWORK["DEFAULT_THROTTLE_RATES"])
    filterset_fields = ["cluster", "node", "container_name", "violation", "source"]
    ordering_fields = ["received_at"]

    @extend_schema(request=ReportBatchSerializer, responses={201: dict})
    def create(self, request, *args, **kwargs):
        payload = request.data
        cluster = self._cluster(request, payload)
        try:
            policy = cluster.rt_policy
        except RTPolicy.DoesNotExist:
            policy = RTPolicy.for_cluster(cluster)
        received = timezone.now()
        try:
            reports = monitoring.parse_batch(payload)
            # With a Kubernetes API, the reconcile (evictions, taints) runs in the rt_reconcile task: the answer
            # waits for the batch to be stored, never for Kubernetes.
            result = monitoring.ingest(cluster, reports, policy=policy, received_at=received, defer=has_api(cluster),
                                       node_ids=monitoring.node_ids_of(cluster))  # fmt: skip
        except InputError as exc:
            raise ValidationError({exc.field or "reports": [str(exc)]}) from exc
        pending = result.pop("pending")
        if pending:
            result["events"] = queue_reconcile(cluster, pending)
        result["queued"] = len(pending)
        return Response({"cluster": cluster.pk, **result}, status=status.HTTP_201_CREATED)

    @staticmethod
    def _cluster(request, payload) -> Cluster:
        pk = payload.get("cluster") if isinstance(payload, dict) else None
        if pk is not None:
            if isinstance(pk, bool) or not isinstance(pk, int | str):
                raise ValidationError({"cluster": ["the id of one of your clusters"]})
            return _visible_cluster(request, pk, with_nodes=True)
        clusters = list(Cluster.objects.select_related("rt_policy").filter(fleet__in=visible_fleets(request))[:2])
        if len(clusters) != 1:
            raise ValidationError({"cluster": ["name the cluster (id): you have several or none"]})
        return clusters[0]


class NodeAdmissionViewSet(ClusterScoped, mixins.CreateModelMixin, viewsets.ReadOnlyModelViewSet):
    """Each node's admissible RT bandwidth and where it comes from. POST (a node agent, with a robot token):
    ``{"cluster": id, "node": name, "capacity": CPUs, "cpus": [...], "source": "...", "kernel": "..."}``, what
    ``python -m continuum.agent admission`` read from the node's kernel. RT-Kube's filter then admits up to it,
    unless the cluster file gives the node an ``rt_threshold`` (which wins); a node that reported nothing keeps
    the thesis' M x 0.95 (``rt_capacity_source`` says which)."""

    queryset = ComputeNode.objects.select_related("cluster")
    serializer_class = NodeAdmissionSerializer
    robot_actions = {"create"}
    filterset_fields = ["cluster", "name", "rt"]

    @extend_schema(request=AdmissionReportSerializer, responses={200: NodeAdmissionSerializer})
    def create(self, request, *args, **kwargs):
        data = AdmissionReportSerializer(data=request.data)
        data.is_valid(raise_exception=True)
        cluster = MonitoringReportViewSet._cluster(request, request.data)
        node = cluster.nodes.filter(name=data.validated_data["node"]).first()
        if node is None:
            raise ValidationError({"node": [f"cluster {cluster.name!r} has no node {data.validated_data['node']!r}"]})
        source = data.validated_data.get("source") or "reported by the node"
        cpus = data.validated_data.get("cpus")
        node.kernel_rt_capacity = data.validated_data["capacity"]
        node.kernel_rt_source = (f"{source}; CPUs {cpus}" if cpus else source)[:300]
        if data.validated_data.get("kernel"):
            node.kernel_rt_source = f"{node.kernel_rt_source[:250]}; Linux {data.validated_data['kernel']}"[:300]
        node.kernel_reported_at = timezone.now()
        node.save(update_fields=["kernel_rt_capacity", "kernel_rt_source", "kernel_reported_at"])
        return Response(NodeAdmissionSerializer(node, context=self.get_serializer_context()).data)


class RTEventViewSet(ClusterScoped, viewsets.ReadOnlyModelViewSet):
    """What the reconcile phase did: evictions (with Eq. 3.19's timestamps) and alerts."""

    queryset = RTEvent.objects.all()
    serializer_class = RTEventSerializer
    filterset_fields = ["cluster", "kind", "node", "container"]
    ordering_fields = ["received_at", "response_ms"]


class NodeTaintViewSet(ClusterScoped, viewsets.ReadOnlyModelViewSet):
    queryset = NodeTaint.objects.select_related("node")
    serializer_class = NodeTaintSerializer
    filterset_fields = ["cluster", "node", "key"]


class RTPodViewSet(ClusterScoped, viewsets.ReadOnlyModelViewSet):
    """The pods the RT scheduler sees, with their node and reserved utilization."""

    queryset = RTPod.objects.all()
    serializer_class = RTPodSerializer
    filterset_fields = ["cluster", "namespace", "node", "criticality"]


class RTDecisionViewSet(ClusterScoped, viewsets.ReadOnlyModelViewSet):
    """The scheduler process's decisions: every node's filter or score on a small cluster, else the top
    candidates, the count of nodes per rejecting filter and an example of each (``decision.rejections``);
    any node's verdict on demand (``why-not``)."""

    queryset = RTDecision.objects.all()
    serializer_class = RTDecisionSerializer
    filterset_fields = ["cluster", "outcome", "namespace", "pod", "node"]

    @extend_schema(
        parameters=[
            OpenApiParameter(
                "node", str, required=False, description="the node to explain (default: every node of the cluster)"
            )
        ],
        responses={200: WhyNotSerializer},
    )
    @action(detail=True, methods=["get"], url_path="why-not")
    def why_not(self, request, pk=None):
        """Why not this node? The pod's verdict on one node (``?node=``) or on every node of the cluster, by
        the scheduler's filters and scores, against the cluster as it is now (400: no such node)."""
        # Not get_object(): its filters would read ``?node=`` as the list filter on the chosen node.
        decision = get_object_or_404(self.get_queryset().select_related("cluster", "realtime"), pk=pk)
        self.check_object_permissions(request, decision)
        query = WhyNotQuerySerializer(data=request.query_params, context=self.get_serializer_context())
        query.is_valid(raise_exception=True)
        return Response(planning.why_not(decision, query.validated_data.get("node")))


class RTPlanViewSet(ClusterScoped, viewsets.ReadOnlyModelViewSet):
    """Placement runs: what-if jobs and scheduler cycles (the engine's PlacementPlan)."""

    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"whatif"})

    queryset = RTPlan.objects.all()
    serializer_class = RTPlanSerializer
    filterset_fields = ["cluster", "kind"]

    @extend_schema(request=WhatIfSerializer, responses={202: JobSerializer})
    @action(detail=False, methods=["post"])
    def whatif(self, request):
        """Start a what-if job: RT-Kube's sort/filter/score over RealTime objects and/or an rtset document."""
        s = WhatIfSerializer(data=request.data, context=self.get_serializer_context())
        s.is_valid(raise_exception=True)
        data = s.validated_data
        cluster = data["cluster"]
        # Bad parameters or containers are the caller's error (400), not a failed job. params_for may create
        # the cluster's default RT policy: inside one transaction, a 400 leaves nothing behind.
        with transaction.atomic():
            planning.params_for(cluster, data.get("params"))
            if data.get("containers") is not None:
                rtset_from_dict(data["containers"], list(cluster.nodes.values_list("name", flat=True)))
        args = {"cluster": cluster.pk, "with_bound": data["with_bound"]}
        for key in ("realtimes", "containers", "params"):
            if key in data:
                args[key] = data[key]
        job = start_job(RealtimeJob.RT_WHATIF, cluster.fleet, args, request.user)
        return Response(JobSerializer(job, context=self.get_serializer_context()).data, status=status.HTTP_202_ACCEPTED)


def register_routes(router) -> None:
    router.register("realtimes", RealTimeViewSet)
    router.register("rt-policies", RTPolicyViewSet)
    router.register("rt-monitorings", MonitoringViewSet)
    router.register("rt-reports", MonitoringReportViewSet)
    router.register("rt-events", RTEventViewSet)
    router.register("rt-admissions", NodeAdmissionViewSet, basename="rt-admission")
    router.register("rt-taints", NodeTaintViewSet)
    router.register("rt-pods", RTPodViewSet)
    router.register("rt-decisions", RTDecisionViewSet)
    router.register("rt-plans", RTPlanViewSet)
