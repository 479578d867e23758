"""The monitoring batch endpoint at the trust boundary (issue 10): a batch is validated whole before anything
happens (counters within the columns' range, finite time stamps in a sane range, text the columns can hold),
and every report carries an idempotency key, so a robot retrying a batch never causes a second eviction."""

import pytest
from django.utils import timezone

from apps.realtime import monitoring
from apps.realtime.models import Monitoring, MonitoringReport, NodeTaint, RTEvent, RTPod, RTPolicy

pytestmark = pytest.mark.django_db

COUNT_MAX = 2**31 - 1


def spec(container="slam", node="node0", period=0, total=0, **extra):
    return {"node": node, "containerName": container, "missedDeadlinesPeriod": period, "missedDeadlinesTotal": total,
            **extra}  # fmt: skip


def monitoring_object(container="slam", period=0, total=0, **extra):
    return {"apiVersion": "rt.monitoring/v1alpha1", "kind": "Monitoring", "metadata": {"name": container},
            "spec": spec(container, period=period, total=total, **extra)}  # fmt: skip


def post(api, cluster, *reports):
    return api.post("/api/v1/rt-reports/", {"cluster": cluster.pk, "reports": list(reports)}, format="json")


def nothing_happened():
    assert RTEvent.objects.count() == 0 and NodeTaint.objects.count() == 0
    assert MonitoringReport.objects.count() == 0 and Monitoring.objects.count() == 0
    assert RTPod.objects.filter(deleted_at__isnull=False).count() == 0


def test_an_overflowing_second_report_is_a_400_before_the_first_one_evicts(api, rt_cluster, node0_pods):
    """The reproduction: report 0 is over the threshold (an eviction), report 1's counter overflows the
    integer column. It used to answer 500 after report 0's eviction and taint were committed."""
    response = post(api, rt_cluster, spec(period=50, total=50), spec("cam", period=1, total=COUNT_MAX + 1))
    assert response.status_code == 400, response.data
    assert f"reports[1].missedDeadlinesTotal: {COUNT_MAX + 1} is larger than {COUNT_MAX}" in str(response.data)
    nothing_happened()
    # In a Monitoring object the field is under spec; 64-bit and larger values are refused the same way.
    response = post(api, rt_cluster, monitoring_object(period=50, total=50),
                    monitoring_object("cam", period=2**63, total=2**64))  # fmt: skip
    assert response.status_code == 400
    assert "reports[1].spec.missedDeadlinesPeriod" in str(response.data["reports"]), response.data
    nothing_happened()
    # The largest value the column holds is accepted.
    response = post(api, rt_cluster, spec("cam", period=COUNT_MAX, total=COUNT_MAX, node="node3"))
    assert response.status_code == 201, response.data
    assert MonitoringReport.objects.get().missed_total == COUNT_MAX


@pytest.mark.parametrize(
    ("bad", "message"),
    [
        (spec("x", sentAt=1e20), "reports[1].sentAt: 1e+20 is not a time between 2000 and 2100"),
        (spec("x", missAt=-1e12), "reports[1].missAt: -1000000000000.0 is not a time between 2000 and 2100"),
        (spec("x", sentAt="9999-12-31T23:59:59+00:00"), "reports[1].sentAt: '9999-12-31T23:59:59+00:00' is not a time"),
        (spec("x", sentAt=[1]), "reports[1].sentAt: must be an RFC 3339 time"),
        (spec("x" * 254), "reports[1].containerName: must be at most 253 printable characters"),
        (spec("x\u0000y"), "reports[1].containerName: contains a NUL character"),
        (spec("x", pod="p\nq"), "reports[1].pod: must be at most 253 printable characters"),
        (spec("x", report_id="a b"), "reports[1].report_id: 'a b' is not a report id"),
        (spec("x", id={"x": 1}), "reports[1].id: {'x': 1} is not a report id"),
        (monitoring_object("x", reportId="y" * 200), "reports[1].spec.reportId"),
    ],
)  # fmt: skip
def test_bad_fields_are_a_400_naming_the_report_and_field(api, rt_cluster, node0_pods, bad, message):
    response = post(api, rt_cluster, spec(period=50, total=50), bad)
    assert response.status_code == 400, response.data
    assert message in str(response.data["reports"]), response.data
    nothing_happened()


def test_a_retried_batch_evicts_once(api, rt_cluster, node0_pods):
    batch = [spec("cam", "node1", period=1, total=1, sentAt="2026-03-01T10:00:00Z"),
             spec(period=50, total=50, sentAt="2026-03-01T10:00:00.2Z")]  # fmt: skip
    first = post(api, rt_cluster, *batch)
    assert first.status_code == 201, first.data
    assert first.data["stored"] == 2 and first.data["duplicates"] == []
    [event] = first.data["events"]
    assert event["kind"] == "eviction"
    # The robot did not get the answer and sends the same batch again: acknowledged, nothing done again.
    again = post(api, rt_cluster, *batch)
    assert again.status_code == 201, again.data
    assert again.data["accepted"] == 2 and again.data["stored"] == 0 and again.data["duplicates"] == [0, 1]
    assert again.data["report_ids"] == first.data["report_ids"] and again.data["events"] == []
    assert RTEvent.objects.filter(kind="eviction").count() == 1 and NodeTaint.objects.count() == 1
    assert RTPod.objects.filter(deleted_at__isnull=False).count() == 1
    assert MonitoringReport.objects.count() == 2
    # A new report (a later sentAt) with the same counters is news.
    later = post(api, rt_cluster, spec(period=50, total=50, sentAt="2026-03-01T10:00:05Z"))
    assert later.data["stored"] == 1 and len(later.data["events"]) == 1


def test_client_chosen_ids_are_unique_per_cluster(api, rt_cluster, node0_pods, other_api):
    first = post(api, rt_cluster, spec(period=50, total=50, report_id="robot7-000123"))
    assert first.status_code == 201 and len(first.data["events"]) == 1
    assert first.data["report_ids"] == ["robot7-000123"]
    # Same id, other content (the robot's counters moved on while it retried): still the same report.
    again = post(api, rt_cluster, spec(period=60, total=60, report_id="robot7-000123"))
    assert again.data["duplicates"] == [0] and again.data["events"] == []
    assert Monitoring.objects.get(name="slam-node0").missed_total == 50  # a replay does not move the counters
    # The same id twice in one batch: the first counts. An integer id is the same as its text.
    both = post(api, rt_cluster, spec("cam", "node1", 1, 1, id=77), spec("cam", "node1", 2, 3, report_id="77"))
    assert both.data["stored"] == 1 and both.data["duplicates"] == [1]
    assert MonitoringReport.objects.get(report_id="77").missed_total == 1
    assert RTEvent.objects.filter(kind="eviction").count() == 1


def test_a_report_claimed_meanwhile_is_not_reconciled(rt_cluster, node0_pods):
    """Two requests carrying the same report: the reconcile claims the id with the eviction's transaction, so
    the one that comes second does nothing."""
    [report] = monitoring.parse_batch([spec(period=50, total=50, report_id="r1")])
    MonitoringReport.objects.create(
        cluster=rt_cluster, name="other", node="node0", container_name="slam", missed_period=0, missed_total=0,
        received_at=timezone.now(), report_id="r1",
    )  # fmt: skip
    policy = RTPolicy.for_cluster(rt_cluster)
    result = monitoring.ingest(rt_cluster, [report], policy=policy)
    assert result["duplicates"] == [0] and result["events"] == []
    # A stored violation that another reconcile (a redelivered task, the sweep) claimed meanwhile:
    now = timezone.now()
    row = MonitoringReport.objects.create(
        cluster=rt_cluster, name="slam-node0", node="node0", container_name="slam", missed_period=50,
        missed_total=50, violation="period", received_at=now, report_id="r2", reconciled_at=now,
    )  # fmt: skip
    outcome = monitoring.reconcile(rt_cluster, policy, policy.monitor_policy(), report, "period", now, claim=row.pk)
    assert outcome is monitoring.DUPLICATE
    assert monitoring.reconcile_stored(rt_cluster, [row.pk], policy) == []
    assert RTEvent.objects.count() == 0 and NodeTaint.objects.count() == 0
    assert RTPod.objects.filter(deleted_at__isnull=False).count() == 0


def test_a_batch_is_stored_in_one_statement_and_the_last_new_report_of_a_container_wins(
    api, rt_cluster, node0_pods, django_assert_max_num_queries
):
    """Issue 15: the batch (reports + latest counters) is one statement on PostgreSQL; within it, the last
    report of a container that is new wins, and a retried report changes nothing."""
    batch = [spec("cam", "node1", 1, 10, report_id="a"), spec("cam", "node1", 2, 20, report_id="b"),
             spec("gps", "node2", 0, 5, report_id="c")]  # fmt: skip
    assert post(api, rt_cluster, spec("warm", "node3", 0, 0)).status_code == 201  # creates the RT policy
    # the token, the cluster, its nodes and the one INSERT statement
    with django_assert_max_num_queries(4):
        first = post(api, rt_cluster, *batch)
    assert first.status_code == 201 and first.data["stored"] == 3 and first.data["duplicates"] == []
    rows = Monitoring.objects.exclude(container_name="warm")
    latest = {m.container_name: (m.missed_period, m.missed_total) for m in rows}
    assert latest == {"cam": (2, 20), "gps": (0, 5)}
    # "b" again (a duplicate) after a new "d": "d" is the last new report of cam and wins.
    again = post(api, rt_cluster, spec("cam", "node1", 3, 30, report_id="d"), batch[1])
    assert again.status_code == 201 and again.data["stored"] == 1 and again.data["duplicates"] == [1]
    assert Monitoring.objects.get(container_name="cam").missed_total == 30
    assert MonitoringReport.objects.count() == 5


def test_a_deferred_violation_is_stored_first_and_reconciled_exactly_once(rt_cluster, node0_pods):
    """Issue 15: the request stores the batch (violations included) and leaves the reconcile to the
    rt_reconcile task: a report acknowledged is stored before any eviction, and the eviction decided for it is
    carried out once, however often its task runs (a redelivered message, the overdue sweep)."""
    policy = RTPolicy.for_cluster(rt_cluster)
    reports = monitoring.parse_batch([spec("cam", "node1", 1, 1), spec(period=50, total=50, report_id="v1")])
    result = monitoring.ingest(rt_cluster, reports, policy=policy, defer=True)
    assert result["stored"] == 2 and result["violations"] == 1 and result["events"] == []
    [pending] = result["pending"]
    row = MonitoringReport.objects.get(pk=pending)
    assert row.report_id == "v1" and row.violation == "period" and row.reconciled_at is None
    assert RTEvent.objects.count() == 0 and RTPod.objects.filter(deleted_at__isnull=False).count() == 0
    [event] = monitoring.reconcile_stored(rt_cluster, [pending], policy)
    assert event.kind == "eviction" and event.victim.rsplit("/", 1)[1] in {"lidar", "planner"}  # stateless A
    assert event.received_at == row.received_at  # Eq. 3.19 counts from the request, queueing included
    assert MonitoringReport.objects.get(pk=pending).reconciled_at is not None
    # The task again, the sweep, another cluster's task naming the row: nothing more.
    assert monitoring.reconcile_stored(rt_cluster, [pending], policy) == []
    assert monitoring.reconcile_overdue(older_than_s=0) == 0
    assert RTEvent.objects.count() == 1 and RTPod.objects.filter(deleted_at__isnull=False).count() == 1


def test_the_sweep_reconciles_a_violation_whose_task_never_ran(rt_cluster, node0_pods):
    """A broker down when the report came: the violation is stored, unclaimed, and the sweep evicts for it
    once it is overdue (not before: its task may still be on its way)."""
    [report] = monitoring.parse_batch([spec(period=50, total=50)])
    result = monitoring.ingest(rt_cluster, [report], defer=True)
    assert monitoring.reconcile_overdue(older_than_s=3600) == 0
    assert RTEvent.objects.count() == 0 and RTPod.objects.filter(deleted_at__isnull=False).count() == 0
    assert monitoring.reconcile_overdue(older_than_s=0) == 1
    assert RTEvent.objects.get().kind == "eviction"
    assert MonitoringReport.objects.get(pk=result["pending"][0]).reconciled_at is not None
    assert monitoring.reconcile_overdue(older_than_s=0) == 0 and RTEvent.objects.count() == 1


def test_a_poison_row_is_skipped_and_logged_and_the_sweep_goes_on_to_every_other_cluster(
    api, cluster_doc, rt_cluster, node0_pods, caplog
):
    """Issue 25: a violation whose node is deleted before it is handled made the overdue sweep raise and abort its
    loop over all clusters, every 10 s. Now the row is handled (an alert saying why, never tried again) and the
    sweep goes on to the next cluster, whose violation is evicted for."""
    from apps.clusters.models import Cluster, ComputeNode

    from .conftest import make_pod

    response = api.post("/api/v1/clusters/import/", {"name": "later-edge", **cluster_doc}, format="json")
    assert response.status_code == 201, response.data
    other = Cluster.objects.get(pk=response.data["id"])
    assert Cluster.objects.filter(pk__in=[rt_cluster.pk, other.pk]).first().pk == rt_cluster.pk  # the poison first
    make_pod(other, "victim", "node1", "NONE", True, cpu=2)
    make_pod(other, "slam", "node1", "B", True, cpu=1, utilization=0.4)
    [poison] = monitoring.ingest(rt_cluster, monitoring.parse_batch([spec(period=50, total=50)]), defer=True)["pending"]
    [fine] = monitoring.ingest(other, monitoring.parse_batch([spec(node="node1", period=50, total=50)]), defer=True)[
        "pending"
    ]
    ComputeNode.objects.filter(cluster=rt_cluster, name="node0").delete()  # before the violation is handled
    assert monitoring.reconcile_overdue(older_than_s=0) == 2
    assert RTEvent.objects.get(cluster=other).kind == "eviction"
    alert = RTEvent.objects.get(cluster=rt_cluster)
    assert alert.kind == "alert" and "node 'node0' is no longer in the cluster" in alert.message
    assert MonitoringReport.objects.filter(pk__in=[poison, fine], reconciled_at__isnull=True).count() == 0
    assert monitoring.reconcile_overdue(older_than_s=0) == 0  # handled once, not every 10 s


def test_a_row_that_raises_is_logged_and_the_sweep_goes_on(api, cluster_doc, rt_cluster, node0_pods, caplog,
                                                           monkeypatch):  # fmt: skip
    """Any other failure of one cluster's reconcile (a bug, a row the code does not expect) is logged with the
    cluster and the row, and the sweep still reconciles every other cluster's violations."""
    from apps.clusters.models import Cluster

    from .conftest import make_pod

    response = api.post("/api/v1/clusters/import/", {"name": "later-edge", **cluster_doc}, format="json")
    other = Cluster.objects.get(pk=response.data["id"])
    make_pod(other, "victim", "node1", "NONE", True, cpu=2)
    make_pod(other, "slam", "node1", "B", True, cpu=1, utilization=0.4)
    [poison] = monitoring.ingest(rt_cluster, monitoring.parse_batch([spec(period=50, total=50)]), defer=True)["pending"]
    monitoring.ingest(other, monitoring.parse_batch([spec(node="node1", period=50, total=50)]), defer=True)
    real = monitoring.reconcile

    def broken(cluster, *args, **kwargs):
        if cluster.pk == rt_cluster.pk:
            raise RuntimeError("a row the code does not expect")
        return real(cluster, *args, **kwargs)

    monkeypatch.setattr(monitoring, "reconcile", broken)
    assert monitoring.reconcile_overdue(older_than_s=0) == 1
    assert RTEvent.objects.get(cluster=other).kind == "eviction"
    assert f"violation {poison} of cluster {rt_cluster.pk}" in caplog.text and "RuntimeError" in caplog.text
    # The row is left unclaimed: a transient failure is tried again by the next sweep.
    assert MonitoringReport.objects.get(pk=poison).reconciled_at is None


def test_a_taint_that_cannot_be_lifted_is_logged_and_the_others_are_lifted(rt_cluster, caplog, monkeypatch):
    """The taint sweep skips and logs a taint whose lift raises, instead of leaving every later one in place."""
    from datetime import timedelta

    from apps.clusters.models import ComputeNode

    past = timezone.now() - timedelta(seconds=1)
    nodes = {n.name: n for n in ComputeNode.objects.filter(cluster=rt_cluster)}
    for name in ("node0", "node1"):
        nodes[name].taints = [{"key": "rt.monitoring/violation", "value": "true", "effect": "NoSchedule"}]
        nodes[name].save()
    bad = NodeTaint.objects.create(cluster=rt_cluster, node=nodes["node0"], expires_at=past)
    good = NodeTaint.objects.create(cluster=rt_cluster, node=nodes["node1"], expires_at=past)
    real = monitoring._lift

    def poison(taint, now):
        if taint.pk == bad.pk:
            raise RuntimeError("a row the code does not expect")
        return real(taint, now)

    monkeypatch.setattr(monitoring, "_lift", poison)
    assert monitoring.lift_expired_taints() == 1
    assert NodeTaint.objects.get(pk=good.pk).lifted_at is not None
    assert ComputeNode.objects.get(pk=nodes["node1"].pk).taints == []
    assert NodeTaint.objects.get(pk=bad.pk).lifted_at is None  # tried again by the next sweep
    assert f"lifting taint {bad.pk} of node" in caplog.text and "RuntimeError" in caplog.text
