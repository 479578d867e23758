"""RT-Kube's REST API: RealTime objects (validation, Listing 3.33 YAML through the model), fleet scoping, the
monitoring endpoint (batches, malformed input, reconcile with the three victim policies), what-if jobs."""

from datetime import timedelta

import pytest
from django.utils import timezone

from apps.realtime.models import Monitoring, MonitoringReport, NodeTaint, RealTime, RTEvent, RTPlan, RTPod
from tests.conftest import DATA

from .conftest import make_pod, make_rt

pytestmark = pytest.mark.django_db

LISTING = (DATA / "listing_3_33.yaml").read_text()
LISTING_REALTIME = LISTING.split("---\n")[0]


def rt_body(cluster, **kw):
    body = {
        "cluster": cluster.pk,
        "name": "lidar-driver",
        "criticality": "A",
        "period": 100,
        "deadline": 100,
        "wcets": [{"node": "node0", "wcet": 12}, {"node": "node1", "wcet": 8}],
        "stateless": True,
        "cpu": 1,
        "memory_mib": 256,
    }
    body.update(kw)
    return body


@pytest.fixture
def listing_cluster(api):
    """A cluster with the listing's nodes, nodeA and nodeB."""
    from apps.clusters.models import Cluster

    doc = {"name": "lab", "nodes": [{"name": "nodeA", "cpu": 8, "rt": True, "criticality": "C"}, {"name": "nodeB"}]}
    response = api.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 201, response.data
    return Cluster.objects.get(pk=response.data["id"])


# ---- RealTime objects -------------------------------------------------------------------------------------
def test_listing_3_33_round_trips_exactly_through_the_model(api, listing_cluster):
    response = api.post(
        "/api/v1/realtimes/import/", {"cluster": listing_cluster.pk, "yaml": LISTING}, format="json"
    )  # the Deployment document of the listing is skipped
    assert response.status_code == 201, response.data
    [row] = response.data
    assert row["name"] == "example-realtime-data" and row["criticality"] == "C"
    assert (row["period"], row["deadline"]) == (100, 100)
    assert row["wcets"] == [{"node": "nodeA", "wcet": 50}, {"node": "nodeB", "wcet": 60}]
    assert row["utilization"] == {"nodeA": 0.5, "nodeB": 0.6}
    assert row["namespace"] == listing_cluster.namespace
    text = api.get(f"/api/v1/realtimes/{row['id']}/yaml/").content.decode()
    assert text == LISTING_REALTIME
    exported = api.get(f"/api/v1/realtimes/export/?cluster={listing_cluster.pk}").content.decode()
    assert exported == LISTING_REALTIME
    # Importing the exported text again changes nothing.
    again = api.post("/api/v1/realtimes/import/", {"cluster": listing_cluster.pk, "yaml": exported}, format="json")
    assert again.status_code == 201 and again.data[0]["id"] == row["id"]
    assert RealTime.objects.count() == 1
    assert api.get(f"/api/v1/realtimes/{row['id']}/yaml/").content.decode() == LISTING_REALTIME


def test_wcet_order_and_extension_fields_round_trip(api, rt_cluster):
    body = rt_body(rt_cluster, wcets=[{"node": "node1", "wcet": 8}, {"node": "node0", "wcet": 12.5}])
    response = api.post("/api/v1/realtimes/", body, format="json")
    assert response.status_code == 201, response.data
    text = api.get(f"/api/v1/realtimes/{response.data['id']}/yaml/").content.decode()
    assert "- node: node1\n    rtWcet: 8\n  - node: node0\n    rtWcet: 12.5\n" in text
    assert "stateless: true\n" in text and "cpu: 1\n" in text and "memoryMib: 256\n" in text
    RealTime.objects.all().delete()
    response = api.post("/api/v1/realtimes/import/", {"cluster": rt_cluster.pk, "yaml": text}, format="json")
    assert response.status_code == 201, response.data
    row = response.data[0]
    assert (row["stateless"], row["cpu"], row["memory_mib"]) == (True, 1, 256)
    assert api.get(f"/api/v1/realtimes/{row['id']}/yaml/").content.decode() == text


@pytest.mark.parametrize(
    ("change", "field", "message"),
    [
        ({"criticality": "D"}, "criticality", "requires ASIL-D capable platform"),
        ({"period": -5}, "period", "period must be positive"),
        ({"deadline": 0}, "deadline", "deadline must be positive"),
        ({"deadline": 120}, "deadline", "deadline 120 exceeds period 100"),
        ({"wcets": [{"node": "node0", "wcet": 101}]}, "wcets", "wcet 101 on node 'node0' exceeds deadline 100"),
        ({"wcets": [{"node": "node0", "wcet": -1}]}, "wcets", "wcet on node 'node0' must be positive"),
        ({"wcets": [{"node": "jetson", "wcet": 5}]}, "wcets", "unknown node 'jetson'"),
        ({"wcets": [{"node": "node0", "wcet": 5}, {"node": "node0", "wcet": 6}]}, "wcets", "node 'node0' has two"),
        ({"wcets": []}, "wcets", "at least one node"),
        ({"cpu": -1}, "cpu", "greater than or equal to 0"),
        ({"name": "Not_A_DNS_Name"}, "name", "lower-case letters"),
    ],
)
def test_invalid_realtime_is_rejected_with_the_field_and_nothing_stored(api, rt_cluster, change, field, message):
    response = api.post("/api/v1/realtimes/", rt_body(rt_cluster, **change), format="json")
    assert response.status_code == 400, response.data
    assert message in " ".join(str(m) for m in response.data[field]), response.data
    assert RealTime.objects.count() == 0


def test_update_is_validated_against_the_stored_values(api, rt_cluster):
    pk = api.post("/api/v1/realtimes/", rt_body(rt_cluster), format="json").data["id"]
    response = api.patch(f"/api/v1/realtimes/{pk}/", {"deadline": 10}, format="json")
    assert response.status_code == 400
    assert "wcet 12 on node 'node0' exceeds deadline 10" in str(response.data["wcets"])
    response = api.patch(f"/api/v1/realtimes/{pk}/", {"deadline": 50, "period": 60}, format="json")
    assert response.status_code == 200, response.data
    row = RealTime.objects.get(pk=pk)
    assert (row.deadline, row.period, row.dirty) == (50, 60, True)
    assert row.sync_state == RealTime.SyncState.LOCAL  # a model-only cluster: nothing to push to


def test_import_rejects_bad_yaml_whole(api, rt_cluster):
    text = LISTING_REALTIME.replace("nodeA", "node0").replace("nodeB", "node1")
    bad = text + "---\n" + text.replace("example-realtime-data", "second").replace("rtWcet: 60", "rtWcet: 160")
    response = api.post("/api/v1/realtimes/import/", {"cluster": rt_cluster.pk, "yaml": bad}, format="json")
    assert response.status_code == 400
    assert "RealTime 'second': wcet 160 on node 'node1' exceeds deadline 100" in str(response.data)
    assert RealTime.objects.count() == 0
    response = api.post("/api/v1/realtimes/import/", {"cluster": rt_cluster.pk, "yaml": "a: [\n"}, format="json")
    assert response.status_code == 400 and "malformed YAML at line" in str(response.data)


def test_realtimes_are_scoped_to_the_fleet(api, other_api, rt_cluster):
    pk = api.post("/api/v1/realtimes/", rt_body(rt_cluster), format="json").data["id"]
    assert other_api.get(f"/api/v1/realtimes/{pk}/").status_code == 404
    assert other_api.get(f"/api/v1/realtimes/{pk}/yaml/").status_code == 404
    assert other_api.get("/api/v1/realtimes/").data["count"] == 0
    assert other_api.delete(f"/api/v1/realtimes/{pk}/").status_code == 404
    response = other_api.post("/api/v1/realtimes/", rt_body(rt_cluster, name="intruder"), format="json")
    assert response.status_code == 400 and "cluster" in response.data
    response = other_api.post("/api/v1/rt-reports/", {"cluster": rt_cluster.pk, "reports": [report()]}, format="json")
    assert response.status_code == 400 and "cluster" in response.data
    assert other_api.get(f"/api/v1/realtimes/export/?cluster={rt_cluster.pk}").status_code == 400
    assert RealTime.objects.count() == 1 and MonitoringReport.objects.count() == 0
    for path in ("rt-events", "rt-pods", "rt-plans", "rt-decisions", "rt-reports", "rt-monitorings", "rt-taints"):
        assert other_api.get(f"/api/v1/{path}/").status_code == 200


def test_endpoints_need_authentication(client, rt_cluster):
    assert client.get("/api/v1/realtimes/").status_code in (401, 403)
    response = client.post("/api/v1/rt-reports/", {"reports": [report()]}, content_type="application/json")
    assert response.status_code in (401, 403)
    assert MonitoringReport.objects.count() == 0


# ---- monitoring reports -----------------------------------------------------------------------------------
def report(container="slam", node="node0", period=0, total=0, **extra):
    spec = {"node": node, "containerName": container, "missedDeadlinesPeriod": period, "missedDeadlinesTotal": total}
    spec.update(extra)
    return {"apiVersion": "rt.monitoring/v1alpha1", "kind": "Monitoring", "metadata": {"name": container}, "spec": spec}


def post(api, cluster, *reports):
    return api.post("/api/v1/rt-reports/", {"cluster": cluster.pk, "reports": list(reports)}, format="json")


def test_batched_reports_are_stored_with_the_latest_counters(api, rt_cluster):
    bare = {"node": "node1", "containerName": "cam", "pod": "cam-7f", "missedDeadlinesPeriod": 1,
            "missedDeadlinesTotal": 4, "sentAt": "2026-01-02T03:04:05.5Z"}  # fmt: skip
    response = post(api, rt_cluster, report(period=2, total=2), bare, report(period=3, total=5))
    assert response.status_code == 201, response.data
    assert response.data["accepted"] == 3 and response.data["violations"] == 0
    assert MonitoringReport.objects.count() == 3
    latest = {m.name: m for m in Monitoring.objects.all()}
    assert set(latest) == {"slam", "cam-7f-cam"}
    assert (latest["slam"].missed_period, latest["slam"].missed_total) == (3, 5)
    cam = MonitoringReport.objects.get(container_name="cam")
    assert cam.sent_at.isoformat() == "2026-01-02T03:04:05.500000+00:00" and cam.pod == "cam-7f"
    # A single object (no batch wrapper) with the fleet's only cluster implied.
    response = api.post("/api/v1/rt-reports/", report(period=1, total=6), format="json")
    assert response.status_code == 201 and response.data["cluster"] == rt_cluster.pk
    assert Monitoring.objects.get(name="slam").missed_total == 6


@pytest.mark.parametrize(
    ("bad", "message"),
    [
        ({"node": "node0", "containerName": "x", "missedDeadlinesPeriod": -1, "missedDeadlinesTotal": 0},
         "reports[1]: Monitoring 'x': spec.missedDeadlinesPeriod must be an integer >= 0"),
        ({"node": "node0", "containerName": "x", "missedDeadlinesPeriod": 3, "missedDeadlinesTotal": 1},
         "missedDeadlinesTotal 1 < missedDeadlinesPeriod 3"),
        ({"node": "node0", "missedDeadlinesPeriod": 0, "missedDeadlinesTotal": 0}, "spec.containerName is required"),
        ({"node": "jetson", "containerName": "x", "missedDeadlinesPeriod": 0, "missedDeadlinesTotal": 0},
         "reports[1]: node 'jetson' is not a node of cluster 'edge'"),
        ({"node": "node0", "containerName": "x", "missedDeadlinesPeriod": 0, "missedDeadlinesTotal": 0,
          "sentAt": "yesterday"}, "reports[1].sentAt: 'yesterday' is not an RFC 3339 time"),
        ({"kind": "Pod", "spec": {}}, "reports[1]: kind 'Pod' is not Monitoring"),
        ("not an object", "reports[1]: must be a Monitoring object"),
    ],
)  # fmt: skip
def test_a_malformed_report_rejects_the_batch_and_stores_nothing(api, rt_cluster, node0_pods, bad, message):
    response = post(api, rt_cluster, report(period=50, total=50), bad)
    assert response.status_code == 400
    assert message in str(response.data["reports"]), response.data
    assert MonitoringReport.objects.count() == 0 and Monitoring.objects.count() == 0
    assert RTEvent.objects.count() == 0 and NodeTaint.objects.count() == 0


def test_malformed_envelopes(api, rt_cluster):
    for body in ({"cluster": rt_cluster.pk, "reports": []}, {"cluster": rt_cluster.pk, "reports": "x"}, []):
        assert api.post("/api/v1/rt-reports/", body, format="json").status_code == 400
    response = api.post("/api/v1/rt-reports/", {"cluster": "x", "reports": [report()]}, format="json")
    assert response.status_code == 400 and "cluster" in response.data
    assert MonitoringReport.objects.count() == 0


# ---- reconcile --------------------------------------------------------------------------------------------
def test_report_over_the_threshold_evicts_by_the_linear_policy_and_taints(api, rt_cluster, node0_pods):
    # At the threshold (10 by default): nothing happens ("higher than").
    response = post(api, rt_cluster, report(period=10, total=10))
    assert response.status_code == 201 and response.data["events"] == []
    before = timezone.now()
    response = post(api, rt_cluster, report(period=11, total=21))
    assert response.status_code == 201, response.data
    [event] = response.data["events"]
    # Candidates: lower class than B, not C, stateless: lidar and planner; linear by CPU takes planner.
    assert event["kind"] == "eviction" and event["victim"] == f"{rt_cluster.namespace}/planner"
    assert event["trigger"] == "period"
    row = RTEvent.objects.get(pk=event["id"])
    assert sorted(row.candidates) == [f"{rt_cluster.namespace}/lidar", f"{rt_cluster.namespace}/planner"]
    assert row.reconcile_done_at >= row.received_at >= before
    assert "model-only cluster" in row.eviction_error and row.eviction_sent_at is None
    assert RTPod.objects.get(name="planner").deleted_at is not None
    taint = NodeTaint.objects.get()
    assert (taint.node.name, taint.key, taint.effect) == ("node0", "rt.monitoring/violation", "NoSchedule")
    assert abs((taint.expires_at - row.received_at).total_seconds() - 60) < 1e-3
    node0 = rt_cluster.nodes.get(name="node0")
    assert {"key": "rt.monitoring/violation", "value": "true", "effect": "NoSchedule"} in node0.taints
    # The next report evicts the next candidate; then only an alert (no candidate left), once per cooldown.
    assert post(api, rt_cluster, report(period=12, total=33)).data["events"][0]["victim"].endswith("/lidar")
    alert = post(api, rt_cluster, report(period=12, total=45)).data["events"]
    assert alert[0]["kind"] == "alert" and "no container may be evicted" in alert[0]["message"]
    assert post(api, rt_cluster, report(period=12, total=57)).data["events"] == []
    assert RTEvent.objects.filter(kind="alert").count() == 1


@pytest.mark.parametrize(
    ("policy", "victim"),
    [
        ({"eviction_policy": "linear", "linear_resource": "memory"}, "lidar"),
        ({"eviction_policy": "linearithmic"}, "planner"),
        ({"eviction_policy": "quadratic", "traffic": {"slam|planner": 5000}}, "lidar"),
        ({"eviction_policy": "quadratic"}, "planner"),
    ],
)
def test_victim_policies_are_configurable(api, rt_cluster, node0_pods, policy, victim):
    response = api.post("/api/v1/rt-policies/", {"cluster": rt_cluster.pk, **policy}, format="json")
    assert response.status_code == 201, response.data
    [event] = post(api, rt_cluster, report(period=30, total=30)).data["events"]
    assert event["victim"] == f"{rt_cluster.namespace}/{victim}"


def test_total_threshold_with_cooldown(api, rt_cluster, node0_pods):
    pk = api.post("/api/v1/rt-policies/", {"cluster": rt_cluster.pk}, format="json").data["id"]
    response = api.patch(
        f"/api/v1/rt-policies/{pk}/", {"threshold_period": None, "threshold_total": 20, "cooldown_s": 0}, format="json"
    )
    assert response.status_code == 200, response.data
    assert post(api, rt_cluster, report(period=5, total=20)).data["events"] == []
    [first] = post(api, rt_cluster, report(period=5, total=21)).data["events"]
    assert first["trigger"] == "total"
    # The total stays above 20 after the eviction; it triggers again only once it has grown by more than 20.
    assert post(api, rt_cluster, report(period=5, total=40)).data["events"] == []
    [second] = post(api, rt_cluster, report(period=5, total=42)).data["events"]
    assert second["victim"] != first["victim"]


def test_policy_validation(api, rt_cluster):
    bad = [
        ({"threshold_period": None, "threshold_total": None}, "threshold_period"),
        ({"eviction_policy": "random"}, "eviction_policy"),
        ({"k": 0}, "k"),
        ({"traffic": {"a": 1}}, "traffic"),
        ({"taint_duration_s": -1}, "taint_duration_s"),
    ]
    for body, field in bad:
        response = api.post("/api/v1/rt-policies/", {"cluster": rt_cluster.pk, **body}, format="json")
        assert response.status_code == 400 and field in response.data, (body, response.data)


def test_report_for_an_unknown_or_ambiguous_container_raises_an_alert(api, rt_cluster, node0_pods):
    [event] = post(api, rt_cluster, report("ghost", period=99, total=99)).data["events"]
    assert event["kind"] == "alert" and "no pod of container 'ghost' is known on node 'node0'" in event["message"]
    make_pod(rt_cluster, "slam-2", "node0", "B", container="slam")
    [event] = post(api, rt_cluster, report("slam", period=99, total=99)).data["events"]
    assert "2 pods on node 'node0' run a container 'slam'" in event["message"]
    [event] = post(api, rt_cluster, report("slam", period=99, total=99, pod="slam")).data["events"]
    assert event["kind"] == "eviction"


def test_expired_taints_are_lifted(rt_cluster, api, node0_pods):
    from apps.realtime.monitoring import lift_expired_taints

    post(api, rt_cluster, report(period=30, total=30))
    assert lift_expired_taints(rt_cluster) == 0
    NodeTaint.objects.update(expires_at=timezone.now() - timedelta(seconds=1))
    assert lift_expired_taints(rt_cluster) == 1
    assert NodeTaint.objects.get().lifted_at is not None
    assert rt_cluster.nodes.get(name="node0").taints == []


# ---- what-if ------------------------------------------------------------------------------------------------
def test_whatif_job_places_realtime_objects_and_explains_every_node(api, rt_cluster):
    make_rt(rt_cluster, "arm", "C", 8.33, 8, {"node2": 3.8})
    make_rt(rt_cluster, "slam", "B", 100, 100, {"node0": 40, "node1": 25})
    make_rt(rt_cluster, "vision", "A", 100, 100, {"node3": 10})
    response = api.post("/api/v1/rt-plans/whatif/", {"cluster": rt_cluster.pk}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded", job
    plan = RTPlan.objects.get(pk=job["result"]["rt_plan"])
    assert plan.kind == "whatif" and (plan.placed, plan.pending) == (2, 1)
    placed = {p["container"]: p["node"] for p in plan.plan["placements"]}
    assert placed["arm"] == "node2"
    assert placed["slam"] in ("node0", "node1")
    [pending] = plan.plan["pending"]
    assert pending["container"] == "vision"
    assert pending["reasons"]["node3"] == "node has no real-time kernel"
    assert "untolerated taint" not in pending["reasons"]["node3"]
    assert {row["node"] for row in plan.plan["explain"] if row["container"] == "arm"} == {
        "node0", "node1", "node2", "node3"
    }  # fmt: skip
    assert api.get(f"/api/v1/rt-plans/{plan.pk}/").data["placed"] == 2


def test_whatif_starts_from_the_bound_pods_and_honours_active_taints(api, rt_cluster):
    make_rt(rt_cluster, "hog", "A", 1, 1, {"node0": 0.95, "node1": 0.95})
    for i in range(4):  # node1 is full: 4 x 0.95 = 3.8
        make_pod(rt_cluster, f"busy{i}", "node1", "A", utilization=0.95)
    NodeTaint.objects.create(
        cluster=rt_cluster, node=rt_cluster.nodes.get(name="node0"), expires_at=timezone.now() + timedelta(minutes=1)
    )
    job = api.post("/api/v1/rt-plans/whatif/", {"cluster": rt_cluster.pk}, format="json").data
    plan = RTPlan.objects.get(job_id=job["id"])
    [pending] = plan.plan["pending"]
    assert "untolerated taint rt.monitoring/violation=true:NoSchedule" in pending["reasons"]["node0"]
    assert "projected RT utilization 4.7500 > threshold 3.8000" in pending["reasons"]["node1"]
    job = api.post(
        "/api/v1/rt-plans/whatif/", {"cluster": rt_cluster.pk, "with_bound": False}, format="json"
    ).data  # an empty ledger, and the taint still applies
    plan = RTPlan.objects.get(job_id=job["id"])
    assert plan.plan["placements"][0]["node"] == "node1"


def test_whatif_with_an_rtset_document_and_bad_parameters(api, rt_cluster):
    doc = {"containers": [{"name": "x", "criticality": "B", "period": 10, "deadline": 10, "wcet": {"node0": 5}}]}
    job = api.post(
        "/api/v1/rt-plans/whatif/", {"cluster": rt_cluster.pk, "containers": doc, "params": {"k": 4}}, format="json"
    ).data
    plan = RTPlan.objects.get(job_id=job["id"])
    assert plan.plan["params"]["k"] == 4 and plan.plan["placements"][0]["container"] == "x"
    response = api.post("/api/v1/rt-plans/whatif/", {"cluster": rt_cluster.pk, "params": {"k": -1}}, format="json")
    assert response.status_code == 400 and "K must be positive" in str(response.data)
    bad = {"containers": [{"name": "x", "criticality": "A", "period": 10, "deadline": 10, "wcet": {"mars": 5}}]}
    response = api.post("/api/v1/rt-plans/whatif/", {"cluster": rt_cluster.pk, "containers": bad}, format="json")
    assert response.status_code == 400 and "unknown node 'mars'" in str(response.data)
    assert RTPlan.objects.count() == 1


def test_rt_schedule_command_on_a_stored_cluster(rt_cluster, capsys):
    import json

    from django.core.management import call_command

    make_rt(rt_cluster, "arm", "C", 8.33, 8, {"node2": 3.8})
    call_command("rt_schedule", "--cluster-id", str(rt_cluster.pk), "--json")
    result = json.loads(capsys.readouterr().out)
    assert result["placements"] == [{"container": "arm", "node": "node2", "score": pytest.approx(1 - 3.8 / 8.33 / 3.8)}]
    assert result["utilization"]["node2"] == pytest.approx(3.8 / 8.33)


def test_whatif_replaces_the_pods_of_its_objects_and_ignores_expired_taints(api, rt_cluster):
    arm = make_rt(rt_cluster, "arm", "C", 1, 1, {"node2": 0.95})
    for i in range(4):  # node2 is full, but only with arm's own pods: the what-if places arm again
        make_pod(rt_cluster, f"arm-{i}", "node2", "C", realtime=arm, utilization=0.95)
    node2 = rt_cluster.nodes.get(name="node2")
    node2.taints = [{"key": "rt.monitoring/violation", "value": "true", "effect": "NoSchedule"}]
    node2.save()
    NodeTaint.objects.create(cluster=rt_cluster, node=node2, expires_at=timezone.now() - timedelta(seconds=1))
    job = api.post("/api/v1/rt-plans/whatif/", {"cluster": rt_cluster.pk}, format="json").data
    plan = RTPlan.objects.get(job_id=job["id"])
    assert plan.plan["placements"] == [{"container": "arm", "node": "node2", "score": pytest.approx(0.75)}]


def test_the_beat_task_lifts_expired_taints(api, rt_cluster, node0_pods):
    from apps.realtime.tasks import rt_lift_taints

    post(api, rt_cluster, report(period=30, total=30))
    assert rt_lift_taints() == 0
    NodeTaint.objects.update(expires_at=timezone.now() - timedelta(seconds=1))
    assert rt_lift_taints() == 1 and rt_cluster.nodes.get(name="node0").taints == []


def test_a_stored_rt_plan_reads_back_as_the_engine_type(api, rt_cluster):
    """RTPlan.plan is PlacementPlan.to_dict() plus ``explain``; RTPlan.engine_plan() reads it back (issue 11)."""
    make_rt(rt_cluster, "arm", "C", 8.33, 8, {"node2": 3.8})
    make_rt(rt_cluster, "vision", "A", 100, 100, {"node3": 10})
    response = api.post("/api/v1/rt-plans/whatif/", {"cluster": rt_cluster.pk}, format="json")
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    row = RTPlan.objects.get(pk=job["result"]["rt_plan"])
    plan = row.engine_plan()
    assert {**plan.to_dict(), "explain": row.plan["explain"]} == row.plan
    assert plan.placed() == {"arm": "node2"} and plan.decision("vision").pending
    assert plan.decision("vision").reasons()["node3"] == "node has no real-time kernel"
