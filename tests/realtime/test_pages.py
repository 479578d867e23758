"""RT dashboard pages: login, fleet scoping, what the cluster page shows, the what-if button, the charts."""

from datetime import timedelta

import pytest
from django.urls import reverse
from django.utils import timezone

from apps.realtime import charts
from apps.realtime.models import RTDecision, RTEvent, RTPlan

from .conftest import make_pod, make_rt

pytestmark = pytest.mark.django_db


@pytest.fixture
def rt_data(api, rt_cluster, node0_pods):
    """RealTime objects, reports over the threshold (an eviction, a taint), a pending pod and its decision."""
    slam = make_rt(rt_cluster, "slam", "B", 100, 100, {"node0": 40})
    make_rt(rt_cluster, "vision", "A", 50, 50, {"node3": 5})
    node0_pods["slam"].realtime = slam
    node0_pods["slam"].save()
    make_pod(rt_cluster, "vision", "", "A")
    spec = {"node": "node0", "containerName": "slam", "missedDeadlinesPeriod": 3, "missedDeadlinesTotal": 3}
    api.post("/api/v1/rt-reports/", {"cluster": rt_cluster.pk, "reports": [spec]}, format="json")
    spec.update(missedDeadlinesPeriod=14, missedDeadlinesTotal=17)
    response = api.post("/api/v1/rt-reports/", {"cluster": rt_cluster.pk, "reports": [spec]}, format="json")
    assert response.data["events"][0]["kind"] == "eviction"
    now = timezone.now()
    for i, ms in enumerate([12.5, 20.0, 31.0, 95.0]):
        RTEvent.objects.create(
            cluster=rt_cluster, kind="eviction", node="node1", container="x", victim=f"v{i}", received_at=now,
            response_ms=ms, response={"reconcile": ms - 2, "trans_kill": 2.0, "total": ms},
        )  # fmt: skip
    verdicts = [{"node": "node3", "rejected_by": "RealTimeNode", "reason": "node has no real-time kernel",
                 "scores": {}, "total": None}]  # fmt: skip
    decision = RTDecision.objects.create(
        cluster=rt_cluster, namespace=rt_cluster.namespace, pod="vision", criticality="A", outcome="pending",
        message="0/4 nodes are available", decision={"item": "x", "node": None, "score": None, "verdicts": verdicts},
    )  # fmt: skip
    return {"cluster": rt_cluster, "decision": decision}


def urls(cluster, decision, plan=None):
    out = [
        reverse("realtime:overview"),
        reverse("realtime:cluster", args=[cluster.pk]),
        reverse("realtime:decision", args=[decision.pk]),
    ]
    if plan is not None:
        out.append(reverse("realtime:plan", args=[plan.pk]))
    return out


def test_pages_require_login(client, rt_data):
    for url in urls(rt_data["cluster"], rt_data["decision"]):
        response = client.get(url)
        assert response.status_code == 302 and response["Location"].startswith(reverse("login")), url
    response = client.post(reverse("realtime:whatif", args=[rt_data["cluster"].pk]))
    assert response.status_code == 302 and RTPlan.objects.count() == 0


def test_other_fleets_get_404(client, rt_data, fleets, django_user_model):
    outsider = django_user_model.objects.create_user("beta-operator", password="x-pass-12345")
    fleets[1].members.add(outsider)
    client.force_login(outsider)
    cluster, decision = rt_data["cluster"], rt_data["decision"]
    assert client.get(reverse("realtime:cluster", args=[cluster.pk])).status_code == 404
    assert client.get(reverse("realtime:decision", args=[decision.pk])).status_code == 404
    assert client.post(reverse("realtime:whatif", args=[cluster.pk])).status_code == 404
    page = client.get(reverse("realtime:overview")).content.decode()
    assert cluster.name not in page


def test_cluster_page_shows_containers_utilization_timeline_and_response_time(member, rt_data):
    cluster = rt_data["cluster"]
    response = member.get(reverse("realtime:cluster", args=[cluster.pk]))
    assert response.status_code == 200
    page = response.content.decode()
    for chart in ("utilization-chart", "timeline-chart", "response-chart"):
        assert f'id="{chart}"' in page, chart
    assert "slam" in page and "vision" in page
    assert "node has no real-time kernel" in page  # the pending pod's reason per node
    assert "rt.monitoring/violation=true:NoSchedule" in page  # node0 is tainted
    assert "evicted" in page or "eviction" in page
    nodes = {n["name"]: n for n in response.context["nodes"]}
    assert nodes["node0"]["used"] == pytest.approx(0.4 + 0.12 + 0.5)  # planner was evicted
    assert nodes["node0"]["tainted"] and not nodes["node1"]["tainted"]
    stats = response.context["response_stats"]
    assert stats["n"] == 4 and stats["max"] == 95.0 and stats["mean"] == pytest.approx(39.625)
    assert 'class="active">Real-time' in page  # the nav entry
    overview = member.get(reverse("realtime:overview")).content.decode()
    assert cluster.name in overview and reverse("realtime:cluster", args=[cluster.pk]) in overview


def test_timeline_window_and_decision_page(member, rt_data):
    cluster = rt_data["cluster"]
    response = member.get(reverse("realtime:cluster", args=[cluster.pk]) + "?window=15m")
    assert response.context["window"] == "15m" and response.context["report_count"] == 2
    page = member.get(reverse("realtime:decision", args=[rt_data["decision"].pk])).content.decode()
    assert "RealTimeNode" in page and "node has no real-time kernel" in page


def test_whatif_button_runs_a_job_and_shows_the_plan(member, rt_data):
    cluster = rt_data["cluster"]
    response = member.post(reverse("realtime:whatif", args=[cluster.pk]), {"with_bound": "on"})
    plan = RTPlan.objects.get()
    assert response.status_code == 302 and response["Location"] == reverse("realtime:plan", args=[plan.pk])
    page = member.get(response["Location"]).content.decode()
    assert "vision" in page and "node has no real-time kernel" in page and "slam" in page


def test_charts():
    nodes = [
        {"name": "n1", "rt": True, "criticality": "C", "threshold": 7.6, "cpu": 8, "by_class": {"C": 2.0},
         "tainted": False},
        {"name": "n2", "rt": False, "criticality": "", "threshold": 3.8, "cpu": 4, "by_class": {}, "tainted": True},
    ]  # fmt: skip
    fig = charts.utilization_figure(nodes)
    threshold = next(t for t in fig.data if t.name.startswith("threshold"))
    assert list(threshold.x) == [7.6, 3.8]
    assert [t.name for t in fig.data if t.type == "bar"] == ["class C"]
    assert "tainted" in fig.data[0].y[1]
    now = timezone.now()
    reports = [{"node": "n1", "container": "a", "time": now - timedelta(seconds=s), "missed_period": s,
                "missed_total": 10 + s} for s in range(3)]  # fmt: skip
    events = [{"node": "n1", "time": now, "kind": "eviction", "victim": "b", "container": "a"}]
    taints = [{"node": "n1", "start": now, "end": None}]
    fig = charts.timeline_figure(reports, events, taints, 10, now + timedelta(seconds=60))
    assert {t.name for t in fig.data} >= {"a", "eviction / alert", "node tainted"}
    assert charts.summary([]) == {"n": 0, "mean": None, "p50": None, "p99": None, "max": None}
    s = charts.summary(list(range(1, 101)))
    assert s["p50"] == pytest.approx(50.5) and s["p99"] == pytest.approx(99.01) and s["max"] == 100


def test_a_whatif_job_page_opens_the_plan_page_not_its_api_json(api, member, rt_cluster):
    """Issue 30: a what-if run through a worker (the job page shown while it runs) linked its result to
    /api/v1/rt-plans/<id>/, raw JSON; the link is the plan's page."""
    make_rt(rt_cluster, "arm", "C", 8.33, 8, {"node2": 3.8})
    job = api.post("/api/v1/rt-plans/whatif/", {"cluster": rt_cluster.pk}, format="json").data
    plan = RTPlan.objects.get(job_id=job["id"])
    page = member.get(reverse("jobs:job", args=[job["id"]]))
    assert page.context["result_link"] == reverse("realtime:plan", args=[plan.pk]) == f"/realtime/plans/{plan.pk}/"
    assert f'id="job-result" href="/realtime/plans/{plan.pk}/"' in page.content.decode()
    assert member.get(page.context["result_link"]).status_code == 200
