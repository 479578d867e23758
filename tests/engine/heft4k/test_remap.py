"""Algorithm 2: partial or total remapping after node failures, and the threshold calibration (Fig. 3.31)."""

import dataclasses
import json
import random
from pathlib import Path

import pytest

from continuum.engine import InputError, TaskGraph
from continuum.engine.core.cluster import cluster_platform
from continuum.engine.heft4k.heft4k import heft4k
from continuum.engine.heft4k.remap import CalibrationPoint, calibrate_threshold, calibration_points, decide, remap

from .test_heft4k import random_cluster, random_dag

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture
def mini():
    dag = TaskGraph.from_dict(json.loads((DATA / "heft4k-mini.dag.json").read_text()))
    platform = cluster_platform(json.loads((DATA / "heft4k-mini.cluster.json").read_text()))
    return dag, platform, heft4k(dag, platform)


def rows(schedule):
    return [(a.task, a.processor, a.start, a.finish) for a in schedule.assignments]


def test_partial_remap_when_the_lost_share_is_exactly_the_threshold(mini):
    dag, platform, plan = mini
    r = remap(plan, dag, platform, ["N2"])
    assert r.mode == "partial"
    assert r.lost_share == pytest.approx(0.2)  # B: 9 of 45, not > 20%
    assert r.lost == ["B"] and r.moved == ["B"]
    assert rows(r.schedule) == [("A", "N1", 0, 4), ("C", "N1", 4, 12), ("B", "N1", 12, 15), ("D", "N1", 15, 17)]
    assert r.makespan_before == 15 and r.makespan_after == 17
    # Line 19: niceness from the original ranks, so the locked tasks keep theirs.
    assert {a.task: a.niceness for a in r.schedule.assignments} == {"A": 0, "B": 11, "C": 8, "D": 16}
    assert r.schedule.violations(dag, platform.without(["N2"])) == []
    assert r.elapsed_ms >= 0 and r.to_dict()["mode"] == "partial"


def test_total_remap_when_most_of_the_rank_is_lost(mini):
    dag, platform, plan = mini
    r = remap(plan, dag, platform, ["N1"])
    assert r.mode == "total"
    assert r.lost_share == pytest.approx(0.8)
    assert sorted(r.lost) == ["A", "C", "D"] and sorted(r.moved) == ["A", "C", "D"]
    assert rows(r.schedule) == [("A", "N2", 0, 6), ("C", "N2", 6, 12), ("B", "N2", 12, 17), ("D", "N2", 17, 21)]
    assert r.makespan_after == 21


def test_a_lost_critical_task_forces_a_total_remap(mini):
    dag, platform, plan = mini
    tasks = dict(dag.tasks)
    tasks["B"] = dataclasses.replace(tasks["B"], critical=True)
    critical = TaskGraph(dag.name, tasks, dag.edges)
    r = remap(plan, critical, platform, ["N2"])
    assert r.mode == "total" and r.critical_lost == ["B"]
    assert "critical task 'B'" in r.reason


def test_a_lower_threshold_turns_the_same_failure_total(mini):
    dag, platform, plan = mini
    assert remap(plan, dag, platform, ["N2"], threshold=0.19).mode == "total"


def test_decide_is_strict():
    dag = TaskGraph.from_dict({"tasks": [{"id": x, "cost": {"cpu": 1}} for x in "ab"], "edges": []})
    assert decide(dag, {"a": 1.0, "b": 4.0}, ["a"], 0.2)[0] == "partial"
    assert decide(dag, {"a": 1.0, "b": 3.0}, ["a"], 0.2)[0] == "total"
    assert decide(dag, {"a": 1.0, "b": 4.0}, [], 0.2)[:3] == ("partial", "lost rank share 0.0% <= threshold 20%", 0.0)


@pytest.mark.parametrize("seed", range(10))
def test_partial_remap_never_moves_an_unaffected_task(seed):
    rng = random.Random(seed)
    nodes = [f"n{i}" for i in range(rng.randint(3, 6))]
    dag = random_dag(rng, rng.randint(5, 60), nodes)
    dag = TaskGraph(dag.name, {t: dataclasses.replace(x, critical=False) for t, x in dag.tasks.items()}, dag.edges)
    platform = random_cluster(rng, nodes)
    plan = heft4k(dag, platform)
    failed = [rng.choice(nodes)]
    before = {a.task: a.processor for a in plan.assignments}
    try:
        r = remap(plan, dag, platform, failed, mode="partial")
    except InputError as exc:  # a task only the failed node could run
        assert "cannot run on any processor" in str(exc)
        return
    after = {a.task: a.processor for a in r.schedule.assignments}
    assert all(after[t] == before[t] for t in dag.tasks if before[t] not in failed)
    assert set(r.moved) == set(r.lost) == {t for t in dag.tasks if before[t] in failed}
    assert all(n not in failed for n in after.values())
    assert r.schedule.violations(dag, platform.without(failed)) == []
    full = remap(plan, dag, platform, failed, mode="total")
    assert full.schedule.violations(dag, platform.without(failed)) == []


def test_bad_failures_are_rejected(mini):
    dag, platform, plan = mini
    with pytest.raises(InputError, match="unknown node 'N9'"):
        remap(plan, dag, platform, ["N9"])
    with pytest.raises(InputError, match="no processor is left"):
        remap(plan, dag, platform, ["N1", "N2"])
    with pytest.raises(InputError, match="threshold must be a fraction"):
        remap(plan, dag, platform, ["N2"], threshold=20)
    with pytest.raises(InputError, match="unknown remap mode 'some'"):
        remap(plan, dag, platform, ["N2"], mode="some")
    partial_plan = dataclasses.replace(plan, assignments=plan.assignments[:2])
    with pytest.raises(InputError, match="is not in the current schedule"):
        remap(partial_plan, dag, platform, ["N2"])


def test_calibration_picks_the_largest_threshold_within_delta():
    points = [
        CalibrationPoint(10, "n", 0.05, 10.5, 10.0),  # gap 5%
        CalibrationPoint(10, "n", 0.15, 11.0, 10.0),  # gap 10%
        CalibrationPoint(10, "n", 0.25, 14.0, 10.0),  # gap 40%
    ]
    out = calibrate_threshold(points, delta=0.10, thresholds=[0.1, 0.2, 0.3])
    assert out["threshold"] == 0.2
    assert [round(c["mean_gap"], 4) for c in out["curve"]] == [0.05, 0.075, 0.1833]
    assert calibrate_threshold(points, delta=0.01, thresholds=[0.1, 0.2])["threshold"] is None


def test_calibration_points_on_generated_cases():
    rng = random.Random(5)
    nodes = [f"n{i}" for i in range(4)]
    cases = []
    for _ in range(3):
        dag = random_dag(rng, 20, nodes)
        dag = TaskGraph(
            dag.name,
            {t: dataclasses.replace(x, cost=dict.fromkeys(nodes, 5.0)) for t, x in dag.tasks.items()},
            dag.edges,
        )
        cases.append((dag, random_cluster(rng, nodes)))
    points = calibration_points(cases, seed=1, failures_per_dag=2)
    assert len(points) == 6
    assert all(0.0 <= p.lost_share <= 1.0 and p.partial > 0 and p.total > 0 for p in points)


def test_calibration_by_the_90th_percentile_is_stricter():
    points = [CalibrationPoint(10, "n", 0.1, 10.0, 10.0)] * 8 + [CalibrationPoint(10, "n", 0.1, 13.0, 10.0)] * 2
    assert calibrate_threshold(points, delta=0.10, thresholds=[0.1])["threshold"] == 0.1  # mean gap 6%
    assert calibrate_threshold(points, delta=0.10, thresholds=[0.1], statistic="p90")["threshold"] is None
    with pytest.raises(InputError, match="unknown statistic"):
        calibrate_threshold(points, statistic="max")


def test_marginal_calibration_stops_where_the_added_cases_lose_more_than_delta():
    points = [
        CalibrationPoint(10, "n", 0.05, 10.0, 10.0),
        CalibrationPoint(10, "n", 0.15, 10.2, 10.0),
        CalibrationPoint(10, "n", 0.25, 12.0, 10.0),  # the 20-30% step loses 20%
        CalibrationPoint(10, "n", 0.40, 10.0, 10.0),
    ]
    steps = [0.1, 0.2, 0.3, 0.4, 0.5]
    assert calibrate_threshold(points, 0.10, steps, statistic="marginal")["threshold"] == 0.2
    assert calibrate_threshold(points, 0.10, steps)["threshold"] == 0.5  # the cumulative mean hides it
