"""RT-Kube dashboard pages: every page needs a login and shows only the user's fleets' clusters (404 otherwise)."""

from __future__ import annotations

from collections import defaultdict
from datetime import timedelta

from django.contrib import messages
from django.contrib.auth.decorators import login_required
from django.db.models import Count, Q
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, redirect, render
from django.utils import timezone
from django.views.decorators.http import require_POST

from apps.clusters.models import Cluster
from apps.jobs.services import start_job
from apps.realtime.kinds import RealtimeJob
from apps.tenancy.scoping import visible_fleets
from apps.ui.charts import to_html
from continuum.engine.core.errors import InputError

from . import charts, planning
from .models import Monitoring, MonitoringReport, NodeTaint, RealTime, RTDecision, RTEvent, RTPlan, RTPod, RTPolicy

#: The timeline shows at most this many reports (the latest).
TIMELINE_LIMIT = 5000
WINDOWS = {"15m": 15, "1h": 60, "6h": 360, "24h": 1440}


def clusters_of(request: HttpRequest):
    return Cluster.objects.filter(fleet__in=visible_fleets(request))


@login_required
def overview(request: HttpRequest) -> HttpResponse:
    since = timezone.now() - timedelta(hours=1)
    clusters = (
        clusters_of(request)
        .select_related("fleet")
        .annotate(
            realtime_count=Count("realtimes", distinct=True),
            rt_nodes=Count("nodes", filter=Q(nodes__rt=True), distinct=True),
            pods_bound=Count(
                "rt_pods", filter=Q(rt_pods__deleted_at__isnull=True) & ~Q(rt_pods__node=""), distinct=True
            ),
            pods_pending=Count("rt_pods", filter=Q(rt_pods__deleted_at__isnull=True, rt_pods__node=""), distinct=True),
            evictions=Count(
                "rt_events", filter=Q(rt_events__kind="eviction", rt_events__received_at__gte=since), distinct=True
            ),
        )
        .order_by("name", "pk")
    )
    return render(request, "realtime/overview.html", {"clusters": clusters, "nav": "realtime"})


def _node_rows(cluster: Cluster, pods: list[RTPod], tainted: set[str]) -> list[dict]:
    by_node: dict[str, dict[str, float]] = defaultdict(lambda: defaultdict(float))
    for p in pods:
        if p.node and p.utilization:
            by_node[p.node][p.criticality] += p.utilization
    rows = []
    for n in cluster.nodes.order_by("name"):
        threshold = n.rt_capacity
        used = sum(by_node[n.name].values())
        rows.append(
            {
                "name": n.name,
                "rt": n.rt,
                "criticality": n.criticality,
                "threshold": threshold,
                "cpu": n.cpu,
                "by_class": dict(by_node[n.name]),
                "used": used,
                "percent": 100 * used / threshold if threshold else 0.0,
                "tainted": n.name in tainted,
                "status": n.status,
            }
        )
    return rows


@login_required
def cluster_page(request: HttpRequest, pk: int) -> HttpResponse:
    """One cluster's RT state: node utilization, RealTime objects and pods, the missed-deadline timeline of
    the chosen window, the eviction response times, the RT scheduler's decisions and the what-if plans."""
    cluster = get_object_or_404(clusters_of(request).select_related("fleet"), pk=pk)
    policy = RTPolicy.for_cluster(cluster)
    now = timezone.now()
    window = request.GET.get("window", "1h")
    since = now - timedelta(minutes=WINDOWS.get(window, 60))
    pods = list(RTPod.objects.filter(cluster=cluster, deleted_at__isnull=True).select_related("realtime"))
    return render(
        request,
        "realtime/cluster.html",
        {
            "cluster": cluster,
            "policy": policy,
            **_node_context(cluster, pods, now),
            **_realtime_context(cluster, pods),
            **_timeline_context(cluster, policy, since, now),
            "window": window,
            "windows": list(WINDOWS),
            **_response_context(cluster),
            **_decision_context(cluster, pods),
            "plans": RTPlan.objects.filter(cluster=cluster, kind=RTPlan.Kind.WHATIF)[:10],
            "nav": "realtime",
        },
    )


def _node_context(cluster: Cluster, pods: list[RTPod], now) -> dict:
    """The nodes' RT utilization against their threshold (table and figure) and the taints in force."""
    active_taints = list(
        NodeTaint.objects.filter(cluster=cluster, lifted_at__isnull=True, expires_at__gt=now).select_related("node")
    )
    nodes = _node_rows(cluster, pods, {t.node.name for t in active_taints})
    util_fig = to_html(charts.utilization_figure(nodes), div_id="utilization-chart") if nodes else None
    return {"nodes": nodes, "util_fig": util_fig, "taints": active_taints}


def _realtime_context(cluster: Cluster, pods: list[RTPod]) -> dict:
    """The RealTime objects with their live pods, WCETs and latest missed-deadline reports; the other pods."""
    latest = {m.pod or m.container_name: m for m in Monitoring.objects.filter(cluster=cluster)}
    realtimes = list(cluster.realtimes.prefetch_related("wcets__node", "pods"))
    for rt in realtimes:
        rt.live_pods = [p for p in rt.pods.all() if p.deleted_at is None]
        rt.wcet_list = [(w.node.name, w.wcet, w.wcet / rt.period if rt.period else None) for w in rt.wcets.all()]
        rt.missed = [m for m in (latest.get(p.name) for p in rt.live_pods) if m]
        if not rt.missed and rt.name in latest:
            rt.missed = [latest[rt.name]]
    return {"realtimes": realtimes, "others": [p for p in pods if p.realtime_id is None]}


def _timeline_context(cluster: Cluster, policy: RTPolicy, since, now) -> dict:
    """The timeline of the window: missed-deadline reports (the latest :data:`TIMELINE_LIMIT`), RT events
    and the taints they put on nodes."""
    reports = list(
        MonitoringReport.objects.filter(cluster=cluster, received_at__gte=since)
        .order_by("-received_at")
        .values("node", "container_name", "pod", "received_at", "missed_period", "missed_total")[:TIMELINE_LIMIT]
    )
    report_rows = [
        {
            "node": r["node"],
            "container": r["pod"] or r["container_name"],
            "time": r["received_at"],
            "missed_period": r["missed_period"],
            "missed_total": r["missed_total"],
        }
        for r in reversed(reports)
    ]
    events = list(RTEvent.objects.filter(cluster=cluster, received_at__gte=since).order_by("received_at"))
    event_rows = [
        {"node": e.node, "time": e.received_at, "kind": e.kind, "victim": e.victim, "container": e.container}
        for e in events
    ]
    timeline = None
    if report_rows or event_rows:
        taint_rows = _taint_rows(cluster, since, now)
        fig = charts.timeline_figure(report_rows, event_rows, taint_rows, policy.threshold_period, now)
        timeline = to_html(fig, div_id="timeline-chart")
    return {
        "timeline": timeline,
        "report_count": len(report_rows),
        "limited": len(report_rows) >= TIMELINE_LIMIT,
        "events": events[-25:][::-1],
    }


def _taint_rows(cluster: Cluster, since, now) -> list[dict]:
    """The taints in force during the window, clipped to it."""
    taints = NodeTaint.objects.filter(cluster=cluster, expires_at__gte=since).filter(
        Q(lifted_at__isnull=True) | Q(lifted_at__gte=since)
    )
    rows = []
    for t in taints.select_related("node", "event"):
        start = t.event.received_at if t.event else t.created
        end = min(t.lifted_at or t.expires_at, t.expires_at, now)
        rows.append({"node": t.node.name, "start": max(start, since), "end": end})
    return rows


def _response_context(cluster: Cluster) -> dict:
    """The eviction response times (the latest 2000) and their components, against thesis Table 4.35."""
    responses = list(
        RTEvent.objects.filter(cluster=cluster, kind=RTEvent.Kind.EVICTION, response_ms__isnull=False)
        .order_by("-received_at")
        .values_list("response_ms", "response")[:2000]
    )
    response_ms = [r[0] for r in responses]
    components = {}
    for key in ("update_wait", "trans_json", "reconcile", "trans_kill", "total"):
        values = [r[1][key] for r in responses if isinstance(r[1], dict) and key in r[1]]
        components[key] = charts.summary(values)
    response_fig = to_html(charts.response_figure(response_ms), div_id="response-chart") if response_ms else None
    return {
        "response_fig": response_fig,
        "response_stats": charts.summary(response_ms),
        "components": components,
        "table_4_35": charts.TABLE_4_35,
    }


def _decision_context(cluster: Cluster, pods: list[RTPod]) -> dict:
    """The RT scheduler's latest decisions and the pods waiting for it, each with its last decision."""
    decisions = list(RTDecision.objects.filter(cluster=cluster)[:25])
    pending = [p for p in pods if not p.node and p.scheduler_name == "RT-scheduler"]
    last_decision = {}
    for d in RTDecision.objects.filter(cluster=cluster, outcome="pending").order_by("-created")[:200]:
        last_decision.setdefault((d.namespace, d.pod), d)
    for p in pending:
        p.decision = last_decision.get((p.namespace, p.name))
    return {"decisions": decisions, "pending": pending}


@login_required
@require_POST
def run_whatif(request: HttpRequest, pk: int) -> HttpResponse:
    cluster = get_object_or_404(clusters_of(request).select_related("fleet"), pk=pk)
    if not RealTime.objects.filter(cluster=cluster).exists():
        messages.error(request, "This cluster has no RealTime objects to place.")
        return redirect("realtime:cluster", pk=cluster.pk)
    job = start_job(
        RealtimeJob.RT_WHATIF,
        cluster.fleet,
        {"cluster": cluster.pk, "with_bound": "with_bound" in request.POST},
        request.user,
    )
    if job.state == "succeeded" and (job.result or {}).get("rt_plan"):
        return redirect("realtime:plan", pk=job.result["rt_plan"])
    return redirect("jobs:job", pk=job.pk)


@login_required
def decision_detail(request: HttpRequest, pk: int) -> HttpResponse:
    decision = get_object_or_404(
        RTDecision.objects.filter(cluster__fleet__in=visible_fleets(request)).select_related("cluster", "realtime"),
        pk=pk,
    )
    verdicts = decision.decision.get("verdicts", [])
    rejections = sorted((decision.decision.get("rejections") or {}).items())
    # "Why not node X?" (or every node, ``?node=*``): computed on demand by the scheduler's filters.
    asked = (request.GET.get("node") or "").strip()[:253]
    why, why_error = None, ""
    if asked:
        try:
            why = planning.why_not(decision, None if asked == "*" else asked)
        except InputError as exc:
            why_error = str(exc)
    return render(
        request,
        "realtime/decision.html",
        {
            "decision": decision,
            "verdicts": verdicts,
            "rejections": rejections,
            "asked": asked,
            "why": why,
            "why_error": why_error,
            "cluster": decision.cluster,
            "nav": "realtime",
        },
        status=400 if why_error else 200,
    )


@login_required
def plan_detail(request: HttpRequest, pk: int) -> HttpResponse:
    plan = get_object_or_404(
        RTPlan.objects.filter(cluster__fleet__in=visible_fleets(request)).select_related("cluster", "job"), pk=pk
    )
    doc = plan.plan or {}
    thresholds = doc.get("thresholds", {})
    utilization = []
    for n, u in sorted((doc.get("utilization") or {}).items()):
        limit = thresholds.get(n)
        utilization.append({"node": n, "used": u, "threshold": limit, "percent": 100 * u / limit if limit else 0})
    return render(
        request,
        "realtime/plan.html",
        {
            "plan": plan,
            "doc": doc,
            "decisions": doc.get("decisions", []),
            "utilization": utilization,
            "cluster": plan.cluster,
            "nav": "realtime",
        },
    )
