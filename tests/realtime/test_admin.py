"""Admin forms of the RT resources: the engine's validation (positive numbers, WCET <= D <= P, known nodes,
a supported criticality) with the errors on the offending field or WCET row, and nothing saved on error."""

import pytest

from apps.realtime.models import Monitoring, RealTime

pytestmark = pytest.mark.django_db

ADD = "/admin/realtime/realtime/add/"


@pytest.fixture
def admin(client, django_user_model):
    user = django_user_model.objects.create_superuser("root", "root@example.com", "root-pass-123")
    client.force_login(user)
    return client


def form(cluster, wcets, **fields):
    data = {
        "cluster": cluster.pk,
        "namespace": "continuum",
        "name": "lidar-driver",
        "criticality": "A",
        "period": "100",
        "deadline": "100",
        "cpu": "0",
        "memory_mib": "0",
        "wcets-TOTAL_FORMS": str(len(wcets)),
        "wcets-INITIAL_FORMS": "0",
        "wcets-MIN_NUM_FORMS": "0",
        "wcets-MAX_NUM_FORMS": "1000",
    }
    for i, (node, wcet) in enumerate(wcets):
        data.update({f"wcets-{i}-node": node.pk, f"wcets-{i}-wcet": str(wcet), f"wcets-{i}-position": str(i)})
    data.update(fields)
    return data


def errors(response):
    """Field errors of the main form and of each WCET row, plus the inline's non-form errors."""
    main = dict(response.context["adminform"].form.errors)
    formset = response.context["inline_admin_formsets"][0].formset
    rows = [dict(e) for e in formset.errors]
    return main, rows, list(formset.non_form_errors())


def test_admin_creates_a_valid_realtime_with_its_wcets(admin, rt_cluster):
    n0, n1 = rt_cluster.nodes.get(name="node0"), rt_cluster.nodes.get(name="node1")
    response = admin.post(ADD, form(rt_cluster, [(n1, 8), (n0, 12)]))
    assert response.status_code == 302, errors(response)
    row = RealTime.objects.get()
    assert row.wcet_pairs() == [("node1", 8), ("node0", 12)] and row.dirty
    assert row.to_yaml().startswith("apiVersion: rt.scheduling/v1\nkind: RealTime\nmetadata:\n  name: lidar-driver\n")
    assert admin.get(f"/admin/realtime/realtime/{row.pk}/change/").status_code == 200


@pytest.mark.parametrize(
    ("fields", "field", "message"),
    [
        ({"criticality": "D"}, "criticality", "requires ASIL-D capable platform"),
        ({"period": "0"}, "period", "period must be positive"),
        ({"deadline": "-3"}, "deadline", "deadline must be positive"),
        ({"deadline": "150"}, "deadline", "deadline 150 exceeds period 100"),
        ({"cpu": "-1"}, "cpu", "cpu must be positive, got -1"),
        ({"name": "Bad Name"}, "name", "lower-case letters"),
    ],
)
def test_admin_rejects_bad_fields(admin, rt_cluster, fields, field, message):
    n0 = rt_cluster.nodes.get(name="node0")
    response = admin.post(ADD, form(rt_cluster, [(n0, 12)], **fields))
    assert response.status_code == 200
    main, _, _ = errors(response)
    assert message in " ".join(main[field]), main
    assert RealTime.objects.count() == 0


def test_admin_puts_wcet_errors_on_the_row(admin, rt_cluster, fleets):
    from apps.clusters.models import Cluster, ComputeNode

    n0, n1 = rt_cluster.nodes.get(name="node0"), rt_cluster.nodes.get(name="node1")
    response = admin.post(ADD, form(rt_cluster, [(n0, 12), (n1, 120)]))
    _, rows, _ = errors(response)
    assert "wcet 120 on node 'node1' exceeds deadline 100" in rows[1]["wcet"][0]
    response = admin.post(ADD, form(rt_cluster, [(n0, -2)]))
    _, rows, _ = errors(response)
    assert "must be positive" in " ".join(rows[0]["wcet"])
    # A node of another cluster is not a known node.
    elsewhere = Cluster.objects.create(fleet=fleets[1], name="far")
    far = ComputeNode.objects.create(cluster=elsewhere, name="far-node")
    response = admin.post(ADD, form(rt_cluster, [(far, 5)]))
    _, rows, _ = errors(response)
    assert "node 'far-node' is not a node of cluster 'edge'" in rows[0]["node"][0]
    # No WCET at all.
    response = admin.post(ADD, form(rt_cluster, []))
    _, _, non_form = errors(response)
    assert "give the WCET of at least one node" in non_form[0]
    # The same node twice.
    response = admin.post(ADD, form(rt_cluster, [(n0, 5), (n0, 6)]))
    _, _, non_form = errors(response)
    assert non_form == ["Please correct the duplicate data for node."]
    assert RealTime.objects.count() == 0


def test_monitoring_admin_validates_counters(admin, rt_cluster, fleets):
    from apps.clusters.models import Cluster, ComputeNode

    n0 = rt_cluster.nodes.get(name="node0")
    data = {
        "cluster": rt_cluster.pk,
        "name": "slam",
        "node": n0.pk,
        "container_name": "slam",
        "missed_period": "5",
        "missed_total": "2",
        "received_at_0": "2026-01-01",
        "received_at_1": "00:00:00",
    }
    response = admin.post("/admin/realtime/monitoring/add/", data)
    assert response.status_code == 200
    assert "missedDeadlinesTotal 2 < missedDeadlinesPeriod 5" in str(
        response.context["adminform"].form.errors.as_data()
    )
    far = ComputeNode.objects.create(cluster=Cluster.objects.create(fleet=fleets[1], name="far"), name="far-node")
    response = admin.post("/admin/realtime/monitoring/add/", {**data, "missed_total": "9", "node": far.pk})
    assert "not a node of cluster 'edge'" in str(response.context["adminform"].form.errors.as_data())
    response = admin.post("/admin/realtime/monitoring/add/", {**data, "missed_period": "-1"})
    assert "missed_period" in response.context["adminform"].form.errors
    assert Monitoring.objects.count() == 0
    response = admin.post("/admin/realtime/monitoring/add/", {**data, "missed_total": "9"})
    assert response.status_code == 302 and Monitoring.objects.count() == 1


def test_admin_pages_of_every_rt_model_render(admin, rt_cluster):
    for model in ("realtime", "rtpolicy", "monitoring", "monitoringreport", "rtevent", "nodetaint", "rtpod",
                  "rtdecision", "rtplan"):  # fmt: skip
        assert admin.get(f"/admin/realtime/{model}/").status_code == 200, model
