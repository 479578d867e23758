"""HEFT against the Topcuoglu et al. (2002) example and on generated DAGs."""

import json
import random
from pathlib import Path

import pytest

from continuum.engine import InputError, Platform, TaskGraph
from continuum.engine.device.heft import earliest_slot, heft, upward_ranks

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture
def topcuoglu():
    dag = TaskGraph.from_dict(json.loads((DATA / "topcuoglu.dag.json").read_text()))
    platform = Platform.from_dict(json.loads((DATA / "topcuoglu.platform.json").read_text()))
    return dag, platform


def test_topcuoglu_ranks(topcuoglu):
    ranks = upward_ranks(*topcuoglu)
    expected = [108, 77, 80, 80, 69, 63.333, 42.667, 35.667, 44.333, 14.667]
    assert [round(ranks[str(i)], 3) for i in range(10)] == expected


def test_topcuoglu_makespan_and_order(topcuoglu):
    dag, platform = topcuoglu
    schedule = heft(dag, platform)
    assert schedule.makespan == 80
    # The paper's priority list n1, n3, n4, n2, n5, n6, n9, n7, n8, n10 (0-based here).
    assert [a.task for a in schedule.assignments] == ["0", "2", "3", "1", "4", "5", "8", "6", "7", "9"]
    assert schedule.violations(dag, platform) == []
    path = schedule.critical_path(dag, platform)
    assert path[0] == ("0", 0) and path[-1] == ("9", 0)


def test_insertion_fills_gap():
    assert earliest_slot([0.0, 10.0], [5.0, 20.0], ready=2.0, duration=3.0) == 5.0
    assert earliest_slot([0.0, 10.0], [5.0, 20.0], ready=2.0, duration=6.0) == 20.0
    assert earliest_slot([], [], ready=4.0, duration=1.0) == 4.0


def test_exclusive_implementation_is_honoured():
    dag = TaskGraph.from_dict(
        {
            "tasks": [
                {"id": "a", "cost": {"cpu": 1}},
                {"id": "b", "cost": {"gpu": 1}},
                {"id": "c", "cost": {"cpu": 5, "gpu": 1}},
            ],
            "edges": [{"src": "a", "dst": "b", "data": 1}, {"src": "b", "dst": "c"}],
        }
    )
    platform = Platform.homogeneous(2, 1)
    s = heft(dag, platform)
    where = {a.task: a.processor for a in s.assignments}
    assert where["a"].startswith("cpu") and where["b"] == "gpu0"
    assert s.violations(dag, platform) == []


def test_task_nothing_can_run_is_rejected():
    dag = TaskGraph.from_dict({"tasks": [{"id": "x", "cost": {"gpu": 1}}], "edges": []})
    with pytest.raises(InputError, match="'x' cannot run"):
        heft(dag, Platform.homogeneous(2))


def random_dag(rng: random.Random, n: int, classes=("cpu", "gpu")) -> TaskGraph:
    tasks = []
    for i in range(n):
        cost = {c: rng.choice([0, rng.uniform(1, 20)]) for c in classes if rng.random() < 0.8} or {"cpu": 1.0}
        tasks.append({"id": f"t{i}", "cost": cost})
    edges = [
        {"src": f"t{i}", "dst": f"t{j}", "data": rng.uniform(0, 10)}
        for j in range(n)
        for i in range(j)
        if rng.random() < 3 / n
    ]
    return TaskGraph.from_dict({"tasks": tasks, "edges": edges})


@pytest.mark.parametrize("seed", range(25))
def test_random_schedules_are_valid(seed):
    rng = random.Random(seed)
    dag = random_dag(rng, rng.randint(1, 60))
    platform = Platform.homogeneous(
        rng.randint(1, 4), rng.randint(1, 2), bandwidth=rng.choice([None, 0.5, 2.0]), latency=rng.choice([0.0, 1.0])
    )
    for insertion in (True, False):
        s = heft(dag, platform, insertion=insertion, rank_mode=rng.choice(["mean", "max"]))
        assert s.violations(dag, platform) == []
