"""HEFT4K mapping (look-ahead HEFT on multi-core nodes) and Eq. 3.16 niceness."""

import json
import random
from pathlib import Path

import pytest

from continuum.engine import InputError, Platform, TaskGraph
from continuum.engine.core.cluster import cluster_platform
from continuum.engine.device.heft import heft
from continuum.engine.heft4k import heft4k as h4k
from continuum.engine.heft4k.heft4k import heft4k, map_dag, nice_container, niceness, placements

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture
def mini():
    dag = TaskGraph.from_dict(json.loads((DATA / "heft4k-mini.dag.json").read_text()))
    platform = cluster_platform(json.loads((DATA / "heft4k-mini.cluster.json").read_text()))
    return dag, platform


@pytest.mark.parametrize("lookahead", [True, False])
def test_spec_mini_example_plan_and_niceness(mini, lookahead):
    dag, platform = mini
    s = heft4k(dag, platform, lookahead=lookahead)
    assert s.ranks == {"A": 21, "B": 9, "C": 12, "D": 3}
    rows = [(a.task, a.processor, a.start, a.finish, a.niceness) for a in s.assignments]
    assert rows == [
        ("A", "N1", 0, 4, 0),
        ("C", "N1", 4, 12, 8),
        ("B", "N2", 6, 11, 11),
        ("D", "N1", 13, 15, 16),
    ]
    assert s.makespan == 15
    assert s.violations(dag, platform) == []


def test_niceness_eq_3_16():
    ranks = {"A": 21.0, "B": 9.0, "C": 12.0, "D": 3.0}
    assert niceness(ranks) == {"A": 0, "B": 11, "C": 8, "D": 16}
    # A privileged range: the top task gets nice_high, a rank-0 task nice_low.
    assert niceness({"x": 10.0, "y": 5.0, "z": 0.0}, nice_high=-10, nice_low=10) == {"x": -10, "y": 0, "z": 10}
    assert niceness({"x": 10.0, "y": 5.0}, nice_high=0, nice_low=1) == {"x": 0, "y": 1}  # 0.5 rounds up
    assert niceness({"x": 10.0, "y": 5.0}, nice_high=0, nice_low=1, rounding="floor") == {"x": 0, "y": 0}
    assert niceness({"x": 0.0, "y": 0.0}) == {"x": 0, "y": 0}  # all equal: all top priority


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"nice_high": 5, "nice_low": 0}, "must not exceed nice_low"),
        ({"nice_high": -21}, r"nice_high must be an integer in \[-20, 19\]"),
        ({"nice_low": 20}, "nice_low must be an integer"),
        ({"rounding": "banker"}, "unknown rounding 'banker'"),
    ],
)
def test_niceness_rejects_bad_bounds(kwargs, message):
    with pytest.raises(InputError, match=message):
        niceness({"a": 1.0}, **kwargs)


def random_dag(rng, n, nodes, density=0.25, span=8):
    tasks = []
    for i in range(n):
        cost = {m: rng.randint(1, 20) for m in nodes if rng.random() < 0.85} or {nodes[0]: 3}
        tasks.append({"id": f"t{i}", "cost": cost, "critical": rng.random() < 0.05})
    edges = [
        {"src": f"t{i}", "dst": f"t{j}", "data": rng.choice([0, rng.uniform(1, 5)])}
        for j in range(n)
        for i in range(max(0, j - span), j)
        if rng.random() < density
    ]
    return TaskGraph.from_dict({"tasks": tasks, "edges": edges})


def random_cluster(rng, nodes, max_cores=3):
    links = [
        {"src": a, "dst": b, "bandwidth": rng.uniform(0.5, 1.0), "latency": rng.choice([0, 0.2])}
        for i, a in enumerate(nodes)
        for b in nodes[i + 1 :]
        if rng.random() < 0.7
    ]
    procs = [{"id": m, "cores": rng.randint(1, max_cores)} for m in nodes]
    return Platform.from_dict({"processors": procs, "links": links, "route": True, "routing": "ospf", "bandwidth": 0.6})


@pytest.mark.parametrize("seed", range(12))
def test_plans_are_valid_on_multicore_clusters(seed):
    rng = random.Random(seed)
    nodes = [f"n{i}" for i in range(rng.randint(2, 6))]
    dag = random_dag(rng, rng.randint(3, 60), nodes)
    platform = random_cluster(rng, nodes)
    for lookahead in (True, False):
        s = heft4k(dag, platform, lookahead=lookahead)
        assert s.violations(dag, platform) == []
        assert all(a.core is not None and a.niceness is not None for a in s.assignments)
        top = max(s.ranks, key=s.ranks.get)
        assert next(a.niceness for a in s.assignments if a.task == top) == 0


@pytest.mark.parametrize("seed", range(8))
def test_plain_variant_is_heft_on_single_core_nodes(seed):
    rng = random.Random(100 + seed)
    nodes = [f"n{i}" for i in range(rng.randint(2, 5))]
    dag = random_dag(rng, rng.randint(3, 50), nodes)
    platform = random_cluster(rng, nodes, max_cores=1)
    ours = map_dag(dag, platform, lookahead=False)
    ref = heft(dag, platform)
    assert [(a.task, a.processor, a.start, a.finish) for a in ours.assignments] == [
        (a.task, a.processor, a.start, a.finish) for a in ref.assignments
    ]


@pytest.mark.parametrize("seed", range(8))
def test_vectorised_lookahead_matches_the_loop(seed, monkeypatch):
    rng = random.Random(200 + seed)
    nodes = [f"n{i}" for i in range(rng.randint(2, 8))]
    dag = random_dag(rng, rng.randint(5, 80), nodes)
    platform = random_cluster(rng, nodes)
    monkeypatch.setattr(h4k, "NUMPY_MIN_WORK", 0)
    vec = map_dag(dag, platform)
    monkeypatch.setattr(h4k, "NUMPY_MIN_WORK", 10**9)
    loop = map_dag(dag, platform)
    assert [(a.task, a.processor, a.core, a.start, a.finish) for a in vec.assignments] == [
        (a.task, a.processor, a.core, a.start, a.finish) for a in loop.assignments
    ]


def test_lookahead_avoids_a_greedy_trap():
    # Plain HEFT puts A on the fast node n1, but its heavy output must then travel to B, which only n2
    # can run; looking at B, the look-ahead puts A next to it.
    dag = TaskGraph.from_dict(
        {
            "tasks": [{"id": "A", "cost": {"n1": 1, "n2": 3}}, {"id": "B", "cost": {"n2": 1}}],
            "edges": [{"src": "A", "dst": "B", "data": 10}],
        }
    )
    platform = Platform.from_dict({"processors": [{"id": "n1"}, {"id": "n2"}], "bandwidth": 1.0})
    plain = map_dag(dag, platform, lookahead=False)
    ahead = map_dag(dag, platform)
    assert {a.task: a.processor for a in plain.assignments} == {"A": "n1", "B": "n2"}
    assert plain.makespan == 12
    assert {a.task: a.processor for a in ahead.assignments} == {"A": "n2", "B": "n2"}
    assert ahead.makespan == 4


def test_two_cores_run_two_tasks_at_once():
    dag = TaskGraph.from_dict({"tasks": [{"id": x, "cost": {"cpu": 5}} for x in "abc"], "edges": []})
    platform = Platform.from_dict({"processors": [{"id": "n", "cores": 2}]})
    s = heft4k(dag, platform)
    assert sorted((a.core, a.start) for a in s.assignments) == [(0, 0), (0, 5), (1, 0)]
    assert s.makespan == 10


def test_allowed_nodes_lock_tasks(mini):
    dag, platform = mini
    s = map_dag(dag, platform, allowed={"C": ["N2"], "D": ["N2"]})
    where = {a.task: a.processor for a in s.assignments}
    assert where["C"] == "N2" and where["D"] == "N2"
    assert s.violations(dag, platform) == []
    with pytest.raises(InputError, match="task 'C' cannot run on any of its allowed nodes"):
        map_dag(dag, platform, allowed={"C": ["elsewhere"]})
    with pytest.raises(InputError, match="unknown task 'Z'"):
        map_dag(dag, platform, allowed={"Z": ["N1"]})


def test_placements_carry_the_contract_keys(mini):
    rows = placements(heft4k(*mini))
    assert rows[0] == {"task": "A", "node": "N1", "niceness": 0, "start": 0.0, "finish": 4.0, "core": 0}


def test_nice_container_wraps_the_entrypoint():
    spec = nice_container(7, ["ros2", "run", "nav2"], ["--ros-args"])
    assert spec == {
        "command": ["nice", "-n", "7", "--", "ros2", "run", "nav2"],
        "args": ["--ros-args"],
        "securityContext": {},
    }
    privileged = nice_container(-5, ["/entrypoint.sh"])
    assert privileged["command"][:3] == ["nice", "-n", "-5"]
    assert privileged["securityContext"] == {"capabilities": {"add": ["SYS_NICE"]}}
    with pytest.raises(InputError, match="niceness must be an integer"):
        nice_container(25, ["x"])
    with pytest.raises(InputError, match="command must be a non-empty list"):
        nice_container(0, [])
