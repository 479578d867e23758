"""The cluster-level monitor's reconcile phase and the response time of Eqs. 3.19-3.20 (thesis 3.4, 4.4)."""

import pytest

from continuum.engine import InputError
from continuum.engine.rtkube.rt_victims import (
    ClusterMonitor,
    ContainerInfo,
    MonitoringReport,
    MonitorPolicy,
    NodeCapacity,
    candidates,
    crossing_miss,
    is_violation,
    rec_phase_bound,
    response_time,
    response_time_bound,
    select_victim,
)

NODE = [
    ContainerInfo("arm", "C", stateless=True, cpu=0.9),
    ContainerInfo("slam", "B", stateless=True, cpu=0.6, memory_mib=2000),
    ContainerInfo("lidar", "A", stateless=True, cpu=0.3, memory_mib=100),
    ContainerInfo("camera", "A", stateless=True, cpu=0.5, memory_mib=50),
    ContainerInfo("logger", "A", stateless=False, cpu=0.95),
    ContainerInfo("web", "NONE", stateless=True, cpu=0.1, memory_mib=900),
    ContainerInfo("db", "NONE", stateless=False, cpu=2.0),
    ContainerInfo("hog", "NONE", stateless=True, cpu=0.2, memory_mib=10),
]


def report(container="arm", period=0, total=0, at=0.0):
    return MonitoringReport("jetson", container, period, total, at)


def test_violation_is_strictly_above_the_threshold():
    pol = MonitorPolicy(threshold_period=10, threshold_total=100)
    assert is_violation(report(period=10, total=100), pol) is None
    assert is_violation(report(period=11, total=11), pol) == "period"
    assert is_violation(report(period=0, total=101), pol) == "total"
    only_total = MonitorPolicy(threshold_period=None, threshold_total=5)
    assert is_violation(report(period=50, total=5), only_total) is None


def test_candidate_rules():
    names = {k.name for k in candidates(NODE[0], NODE)}  # violator C
    assert names == {"slam", "lidar", "camera", "web", "hog"}  # no C, no stateful, not itself
    assert {k.name for k in candidates(NODE[2], NODE)} == {"web", "hog"}  # violator A: only NONE
    assert candidates(NODE[5], NODE) == []  # the lowest class has nobody below it


def test_linear_picks_the_biggest_user_of_the_lowest_class():
    assert select_victim(NODE[0], NODE, MonitorPolicy()).name == "hog"  # NONE first: hog 0.2 > web 0.1
    assert select_victim(NODE[0], NODE, MonitorPolicy(linear_resource="memory")).name == "web"
    without_none = [k for k in NODE if k.criticality != "NONE"]
    assert select_victim(NODE[0], without_none, MonitorPolicy()).name == "camera"  # A: 0.5 > 0.3; logger stateful
    assert select_victim(NODE[1], without_none, MonitorPolicy()).name == "camera"


def test_linearithmic_combines_cpu_and_memory():
    pol = MonitorPolicy(eviction_policy="linearithmic")
    cap = NodeCapacity(cpu=8, memory_mib=1000)
    # web: 0.1/8 + 900/1000 = 0.9125 beats hog: 0.2/8 + 0.01
    assert select_victim(NODE[0], NODE, pol, cap).name == "web"
    only_a = [k for k in NODE if k.criticality in ("A", "C")]
    # lidar: 0.0375 + 0.1 = 0.1375 beats camera: 0.0625 + 0.05
    assert select_victim(NODE[0], only_a, pol, cap).name == "lidar"


def test_quadratic_prefers_the_least_connected_container():
    pol = MonitorPolicy(eviction_policy="quadratic")
    cap = NodeCapacity(cpu=8, memory_mib=1000)
    traffic = {("web", "arm"): 50.0, "db|web": 10.0, ("hog", "slam"): 1.0}
    # Both NONE candidates: hog talks 1.0 to the rest, web 60.0 -> hog.
    assert select_victim(NODE[0], NODE, pol, cap, traffic).name == "hog"
    # Without traffic it falls back to the combined use: web.
    assert select_victim(NODE[0], NODE, pol, cap, {}).name == "web"


def test_reconcile_evicts_once_and_taints_for_the_duration():
    mon = ClusterMonitor(MonitorPolicy(threshold_period=10, taint_duration=60.0))
    quiet = mon.reconcile(report(period=10, total=10, at=5.0), NODE)
    assert not quiet.evict and quiet.trigger is None and quiet.taint is None
    d = mon.reconcile(report(period=11, total=21, at=5.0), NODE)
    assert d.evict and d.victim == "hog" and d.trigger == "period"
    assert str(d.taint) == "rt.monitoring/violation=true:NoSchedule" and d.taint.until == 65.0
    assert set(d.candidates) == {"slam", "lidar", "camera", "web", "hog"}
    assert d.to_dict()["taint"] == {
        "key": "rt.monitoring/violation",
        "value": "true",
        "effect": "NoSchedule",
        "until": 65.0,
    }


def test_no_candidate_raises_an_alert_not_an_eviction():
    mon = ClusterMonitor(MonitorPolicy(threshold_period=1))
    d = mon.reconcile(MonitoringReport("jetson", "web", 5, 5, 1.0), NODE)
    assert not d.evict and d.taint is None and "no container may be evicted" in d.alert
    with pytest.raises(InputError, match="'ghost' is not listed on node 'jetson'"):
        mon.reconcile(MonitoringReport("jetson", "ghost", 5, 5, 1.0), NODE)


def test_total_trigger_cools_down():
    mon = ClusterMonitor(MonitorPolicy(threshold_period=None, threshold_total=10, taint_duration=30.0))
    assert mon.reconcile(report(total=11, at=0.0), NODE).evict
    # The total stays above the threshold: not again within the cooldown ...
    assert mon.reconcile(report(total=12, at=10.0), NODE).skipped == "cooldown"
    # ... nor after it unless the total grew by more than the threshold since the action.
    assert mon.reconcile(report(total=21, at=31.0), NODE).skipped == "cooldown"
    assert mon.reconcile(report(total=22, at=31.0), NODE).evict
    mon.forget("arm")
    assert mon.reconcile(report(total=23, at=32.0), NODE).evict


def test_monitoring_object_of_listing_3_37():
    doc = {
        "apiVersion": "rt.monitoring/v1alpha1",
        "kind": "Monitoring",
        "metadata": {"name": "monitoring-test"},
        "spec": {"node": "nodeA", "containerName": "nginx", "missedDeadlinesPeriod": 0, "missedDeadlinesTotal": 0},
    }
    r = MonitoringReport.from_dict(doc, reported_at=3.0)
    assert r == MonitoringReport("nodeA", "nginx", 0, 0, 3.0)
    assert r.to_dict("monitoring-test") == doc
    bad = dict(doc["spec"], missedDeadlinesPeriod=3, missedDeadlinesTotal=2)
    with pytest.raises(InputError, match="missedDeadlinesTotal 2 < missedDeadlinesPeriod 3"):
        MonitoringReport.from_dict({"spec": bad})
    with pytest.raises(InputError, match="must be an integer >= 0"):
        MonitoringReport.from_dict(dict(doc["spec"], missedDeadlinesPeriod=-1))
    with pytest.raises(InputError, match=r"spec\.containerName is required"):
        MonitoringReport.from_dict({"spec": {"node": "a"}})


def test_policy_validation():
    with pytest.raises(InputError, match="at least one"):
        MonitorPolicy(threshold_period=None, threshold_total=None)
    with pytest.raises(InputError, match="eviction_policy"):
        MonitorPolicy(eviction_policy="random")
    with pytest.raises(InputError, match="threshold_period must be a non-negative integer"):
        MonitorPolicy(threshold_period=-1)


def test_response_time_components_of_table_4_35():
    # Average column of Table 4.35 (ms): 50.00 + 9.89 + 23.47 + 8.67 = 92.03.
    rt = response_time(
        miss=1000.0, report_sent=1050.0, report_received=1059.89, kill_sent=1083.36, kill_received=1092.03
    )
    assert rt.update_wait == pytest.approx(50.0)
    assert rt.trans_json == pytest.approx(9.89)
    assert rt.reconcile == pytest.approx(23.47)
    assert rt.trans_kill == pytest.approx(8.67)
    assert rt.rec_phase == pytest.approx(32.14)
    assert rt.total == pytest.approx(92.03)
    with pytest.raises(InputError, match="must not decrease"):
        response_time(10.0, 5.0, 11.0, 12.0, 13.0)


def test_response_time_bounds():
    # Worst case of Table 4.35 in seconds, f_c = 10 Hz: 0.1 + 0.11521 + (0.10809 + 0.08499) = 0.40829.
    assert response_time_bound(10.0, 0.11521, 0.10809 + 0.08499) == pytest.approx(0.40829)
    assert rec_phase_bound(n=18, n_rt=4, t_spec=0.5, t_crd=1.0, eviction_phase=2.0, trans_kill=3.0) == 18 + 4 + 2 + 3
    with pytest.raises(InputError, match="n_RT <= n"):
        rec_phase_bound(2, 3, 1, 1, 1, 1)


def test_crossing_miss():
    misses = [1.0, 2.0, 3.0, 4.0, 5.0]
    assert crossing_miss(misses, threshold=2) == 3.0  # the third miss makes the count exceed 2
    assert crossing_miss(misses, threshold=2, since=2.5) == 5.0
    assert crossing_miss(misses, threshold=5) is None
