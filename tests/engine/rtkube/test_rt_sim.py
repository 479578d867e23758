"""Invariants of the RT simulator (EDF/CBS and FIFO on multi-core nodes, kernel admission, monitor loop)."""

import random

import pytest

from continuum.engine import InputError
from continuum.engine.rtkube.rt_model import cluster_from_dict, rtset_from_dict
from continuum.engine.rtkube.rt_sim import SimParams, fixed_placer, kube_default_placer, rt_kube_placer, simulate
from continuum.engine.rtkube.rt_victims import MonitorPolicy


def nodes(*specs):
    return cluster_from_dict({"nodes": [dict(s) for s in specs]})


def tasks(specs, node_names=("n",)):
    """specs: (name, criticality, wcet_ms, period_ms[, extra])"""
    docs = []
    for i, spec in enumerate(specs):
        name, crit, wcet, period, *extra = spec
        doc = {"name": name, "criticality": crit, "period": period, "deadline": period,
               "wcet": {n: wcet for n in node_names}, "arrival": i * 0.001, "stateless": True}  # fmt: skip
        if extra:
            doc.update(extra[0])
        docs.append(doc)
    return rtset_from_dict({"containers": docs})


def random_taskset(rng, cores, n, bound):
    """Implicit-deadline tasks with integer ms periods whose utilizations sum to at most ``bound``."""
    specs, total = [], 0.0
    for i in range(n):
        period = rng.choice([5, 8, 10, 12, 20, 25, 40, 50])
        wcet = round(rng.uniform(0.05, 0.5) * period, 3)
        if total + wcet / period > bound:
            break
        total += wcet / period
        specs.append((f"t{i}", "A", wcet, period))
    return specs, total


@pytest.mark.parametrize("seed", range(6))
def test_uniprocessor_edf_meets_every_deadline_up_to_u_1(seed):
    rng = random.Random(seed)
    specs, total = random_taskset(rng, 1, 12, 1.0)
    cluster = nodes({"name": "n", "cpu": 1, "rt": True, "rt_threshold": 1.0})
    result = simulate(tasks(specs), cluster, "rt_kube", SimParams(horizon_ms=2000, exec_low=1.0, seed=seed))
    assert all(not s.rejected for s in result.containers.values())
    assert sum(s.missed for s in result.containers.values()) == 0
    assert result.node_busy["n"] == pytest.approx(total, abs=0.02)  # exec = WCET: busy equals U


@pytest.mark.parametrize("seed", range(4))
def test_global_edf_meets_deadlines_under_the_gfb_bound(seed):
    rng = random.Random(100 + seed)
    cores = 4
    specs = []
    for i in range(40):
        period = rng.choice([5, 10, 20, 40])
        specs.append((f"t{i}", "A", round(0.3 * period, 3), period))  # u = 0.3 each
    # GFB: U <= M - (M - 1) u_max = 4 - 3 * 0.3 = 3.1 -> take 10 tasks (3.0).
    specs = specs[:10]
    cluster = nodes({"name": "n", "cpu": cores, "rt": True})
    result = simulate(tasks(specs), cluster, "rt_kube", SimParams(horizon_ms=2000, exec_low=1.0, seed=seed))
    assert sum(s.missed for s in result.containers.values()) == 0
    assert sum(s.jobs for s in result.containers.values()) > 0


def test_overload_without_admission_misses():
    specs = [("a", "A", 6, 10), ("b", "A", 6, 10)]  # U = 1.2 on one core
    cluster = nodes({"name": "n", "cpu": 1, "rt": True, "rt_threshold": 1.0})
    admitted = simulate(tasks(specs), cluster, "rt_kube", SimParams(horizon_ms=1000, exec_low=1.0))
    # RT-Kube's filter keeps b pending; nothing misses.
    assert admitted.pending == ["b"] and sum(s.missed for s in admitted.containers.values()) == 0
    bypass = simulate(
        tasks(specs),
        cluster,
        fixed_placer({"a": "n", "b": "n"}),
        SimParams(horizon_ms=1000, exec_low=1.0, admission=False),
    )
    assert sum(s.missed for s in bypass.containers.values()) > 0
    # Work-conserving: once both tasks have released (random phases < 10 ms), the core never idles.
    assert bypass.node_busy["n"] >= 0.99


def test_kernel_rejects_in_arrival_order_and_rejected_tasks_miss_everything():
    rng = random.Random(7)
    specs = [(f"t{i}", "A", 2.9, rng.choice([14.5, 18.1, 24.2])) for i in range(72)]
    cluster = nodes({"name": "J", "cpu": 8, "rt": True, "criticality": "A", "taints": []})
    containers = tasks(specs, ("J",))
    result = simulate(containers, cluster, kube_default_placer(0), SimParams(horizon_ms=500))
    utils = {c.name: c.utilization("J") for c in containers}
    admitted = result.admitted_utilization["J"]
    rejected = [s for s in result.containers.values() if s.rejected]
    assert admitted <= 7.6 + 1e-9
    assert admitted > 7.6 - max(utils.values())
    total = sum(utils.values())
    rejected_u = sum(utils[s.name] for s in rejected)
    assert total - 7.6 - 1e-9 <= rejected_u <= total - 7.6 + max(utils.values())
    for s in rejected:
        assert s.missed == s.jobs == s.rejected_jobs > 0


def test_cbs_isolates_an_overrunning_task_fifo_does_not():
    # One core: "hog" (C, highest FIFO priority) declares 4 of 10 ms but runs 2.5x that; "victim" (A) 4 of 10.
    specs = [("hog", "C", 4, 10), ("victim", "A", 4, 10)]
    cluster = nodes({"name": "n", "cpu": 1, "rt": True, "rt_threshold": 1.0, "criticality": "C"})
    mapping = fixed_placer({"hog": "n", "victim": "n"})
    common = {"horizon_ms": 1000, "exec_low": 1.0, "demand_factor": {"hog": 2.5}, "random_phase": False}
    edf = simulate(tasks(specs), cluster, mapping, SimParams(policy="deadline", **common))
    assert edf.containers["victim"].missed == 0
    assert edf.containers["hog"].overruns == edf.containers["hog"].missed > 0
    fifo = simulate(
        tasks(specs), cluster, fixed_placer({"hog": "n", "victim": "n"}), SimParams(policy="fifo", **common)
    )
    assert fifo.containers["hog"].missed == 0  # highest priority, full core
    assert fifo.containers["victim"].missed == fifo.containers["victim"].jobs > 0
    assert fifo.containers["hog"].overruns == fifo.containers["hog"].jobs  # SIGXCPU at WCET on every job


def test_overrun_probability_and_stress_interference():
    specs = [(f"t{i}", "A", 2, 10) for i in range(4)]
    cluster = nodes({"name": "n", "cpu": 2, "rt": True, "taints": []})
    # Overruns of at most 1 % past the WCET, so a throttled job hardly delays the next one of its task.
    base = SimParams(horizon_ms=3000, p_overrun_stress=0.2, overrun_high=1.01, seed=3)
    quiet = simulate(tasks(specs), cluster, "rt_kube", base)
    assert sum(s.overruns for s in quiet.containers.values()) == 0
    stressed_set = tasks(specs) + rtset_from_dict({"containers": [{"name": "stress", "arrival": 0}]})
    noisy = simulate(stressed_set, cluster, "rt_kube", base)
    jobs = sum(s.jobs for s in noisy.containers.values())
    overruns = sum(s.overruns for s in noisy.containers.values())
    assert 0.15 < overruns / jobs < 0.27  # p_ov = 0.2 with one stress container
    assert sum(s.missed for s in noisy.containers.values()) >= overruns  # a throttled job ends late


def test_same_seed_same_result_and_job_counts():
    specs = [(f"t{i}", "B", 1, p) for i, p in enumerate([5, 7, 11, 13])]
    cluster = nodes({"name": "n", "cpu": 2, "rt": True})
    params = SimParams(horizon_ms=1000, p_overrun=0.1, seed=11)
    r1 = simulate(tasks(specs), cluster, "rt_kube", params)
    r2 = simulate(tasks(specs), cluster, "rt_kube", params)
    assert r1.to_dict() == r2.to_dict()
    for name, period in zip(["t0", "t1", "t2", "t3"], [5, 7, 11, 13], strict=True):
        # Jobs counted: completed ones plus unfinished ones due inside the horizon; the phase is < P.
        assert 1000 // period - 1 <= r1.containers[name].jobs <= 1000 // period + 1
    r3 = simulate(tasks(specs), cluster, "rt_kube", SimParams(horizon_ms=1000, p_overrun=0.1, seed=12))
    assert r3.to_dict() != r1.to_dict()


def test_table_4_32_dynamic_rows_in_the_simulator():
    cluster = nodes(
        {"name": "N1", "cpu": 8, "rt": True, "taints": []},
        {"name": "N2", "cpu": 8, "rt": True, "taints": []},
    )
    docs = [{"name": f"a{i}", "criticality": "A", "period": 4.0, "deadline": 4.0, "wcet": {"N1": 3.8, "N2": 3.8},
             "arrival": 0} for i in range(16)]  # fmt: skip
    docs.append({"name": "new", "criticality": "A", "period": 4.0, "deadline": 4.0, "wcet": {"N1": 3.8, "N2": 3.8},
                 "arrival": 100})  # fmt: skip
    containers = rtset_from_dict({"containers": docs})
    params = SimParams(horizon_ms=300, exec_low=0.9)
    rt = simulate(containers, cluster, "rt_kube", params)
    assert rt.pending == ["new"] and not any(s.rejected for s in rt.containers.values())
    initial = {f"a{i}": "N1" if i < 8 else "N2" for i in range(16)}
    for seed in range(3):
        native = simulate(containers, cluster, fixed_placer(initial, kube_default_placer(seed)), params)
        assert native.pending == [] and [s.name for s in native.containers.values() if s.rejected] == ["new"]
        assert native.containers["new"].missed == native.containers["new"].jobs > 0


def hog_cluster():
    return nodes(
        {"name": "J", "cpu": 2, "rt": True, "criticality": "C"},
        {"name": "S", "cpu": 4, "rt": True, "criticality": "A"},
    )


def hog_set():
    # J has 2 cores: the C tasks use 1.4 of them, the hog 0.9 more -> 2.3, an overload.
    specs = [("arm", "C", 5, 10, {"stateless": False}), ("cam", "C", 4, 10, {"stateless": False}),
             ("ctl", "C", 5, 10, {"stateless": False}), ("hog", "A", 9, 10)]  # fmt: skip
    return tasks(specs, ("J", "S"))


def test_monitor_evicts_the_hog_taints_the_node_and_it_restarts_elsewhere():
    # Fig. 4.21: a hog placed on the Jetson past the filter; misses cross the threshold, the monitor
    # evicts it (lower class, stateless, highest CPU) and taints J; RT-Kube restarts it on S.
    policy = MonitorPolicy(threshold_period=3, taint_duration=30.0)
    params = SimParams(horizon_ms=4000, exec_low=1.0, monitor=policy, bypass_admission=frozenset({"hog"}),
                       record_reports=True, cold_start_ms=500)  # fmt: skip
    placer = fixed_placer({"arm": "J", "cam": "J", "ctl": "J", "hog": "J"}, rt_kube_placer())
    r = simulate(hog_set(), hog_cluster(), placer, params)
    assert len(r.evictions) == 1
    ev = r.evictions[0]
    assert (ev.node, ev.victim, ev.new_node) == ("J", "hog", "S") and ev.violator in {"arm", "cam", "ctl"}
    assert r.containers["hog"].node == "S" and r.containers["hog"].evictions == 1
    assert ev.taint_until_ms == pytest.approx(ev.time_ms - 23 + 30_000)  # tainted at reconcile time for 30 s
    # Eq. 3.19 components: update wait <= 1/f_c, then the modelled transfer and reconcile delays.
    rt = ev.response_time
    assert 0 <= rt.update_wait <= 100 and rt.trans_json == 3 and rt.reconcile == 20 and rt.trans_kill == 3
    # After the eviction (and a settling period) the C containers on J stop missing deadlines.
    late = [x for x in r.reports if x["time_ms"] > ev.time_ms + 100 and x["containerName"] != "hog"]
    assert late and all(x["missedDeadlinesPeriod"] == 0 for x in late)
    before = [x for x in r.reports if x["time_ms"] < ev.time_ms and x["containerName"] != "hog"]
    assert any(x["missedDeadlinesPeriod"] > 3 for x in before)
    # The restarted hog honours its budget on S and meets its deadlines there.
    assert r.node_busy["S"] > 0


def test_monitor_without_candidates_raises_alerts():
    specs = [("arm", "C", 6, 10), ("cam", "C", 6, 10)]
    cluster = nodes({"name": "J", "cpu": 1, "rt": True, "criticality": "C", "rt_threshold": 1.0})
    params = SimParams(horizon_ms=1000, exec_low=1.0, monitor=MonitorPolicy(threshold_period=2), admission=False)
    r = simulate(tasks(specs, ("J",)), cluster, fixed_placer({"arm": "J", "cam": "J"}), params)
    assert r.evictions == [] and r.alerts and "no container may be evicted" in r.alerts[0]["message"]


def test_bad_parameters():
    with pytest.raises(InputError, match="policy must be deadline or fifo"):
        SimParams(policy="rr")
    with pytest.raises(InputError, match="exec_low"):
        SimParams(exec_low=0)
    with pytest.raises(InputError, match="unknown placer"):
        simulate([], nodes({"name": "n"}), "magic")


def test_a_pending_container_is_bound_when_the_taint_expires():
    policy = MonitorPolicy(threshold_period=3, taint_duration=1.0)
    params = SimParams(horizon_ms=3000, exec_low=1.0, monitor=policy, bypass_admission=frozenset({"hog"}),
                       cold_start_ms=500)  # fmt: skip
    late = rtset_from_dict({"containers": [{"name": "late", "criticality": "C", "period": 10, "deadline": 10,
                                            "wcet": {"J": 1}, "arrival": 500}]})  # fmt: skip
    placer = fixed_placer({"arm": "J", "cam": "J", "ctl": "J", "hog": "J"}, rt_kube_placer())
    r = simulate(hog_set() + late, hog_cluster(), placer, params)
    [ev] = r.evictions
    assert ev.time_ms < 500 < ev.taint_until_ms
    waiting = [p for p in r.plans if "late" in {d.item for d in p.decisions} and p.placed().get("late") is None]
    assert waiting and waiting[0].metrics["time_ms"] == 500
    assert waiting[0].to_dict()["pending"][0]["reasons"]["J"].startswith("untolerated taint rt.monitoring/violation")
    bound = [p for p in r.plans if p.placed().get("late") == "J"]
    assert len(bound) == 1 and bound[0].metrics["time_ms"] == pytest.approx(ev.taint_until_ms)
    assert r.containers["late"].node == "J" and r.containers["late"].jobs > 0
