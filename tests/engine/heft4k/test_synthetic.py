"""The Table 4.28-like generator: seeded, within the table's ranges, and valid for every scheduler."""

import random

import pytest

from continuum.engine.heft4k.synthetic import corpus_stats, critical_path_length, dag_stats, random_cluster, random_dag


def test_generator_is_seeded_and_in_range():
    a = random_dag(random.Random(4), ["n0", "n1"])
    b = random_dag(random.Random(4), ["n0", "n1"])
    assert a.to_dict() == b.to_dict()
    assert 4 <= len(a) <= 511
    for t in a.tasks.values():
        assert set(t.cost) == {"n0", "n1"} and all(1 <= c <= 20 and c == int(c) for c in t.cost.values())
    assert all(1 <= e.data <= 5 for e in a.edges)


def test_every_task_below_the_first_level_has_a_parent():
    dag = random_dag(random.Random(1), ["n0"], n=200)
    has_parent = {e.dst for e in dag.edges}
    roots = [t for t in dag.tasks if t not in has_parent]
    assert 1 <= len(roots) < len(dag)
    assert dag_stats(dag)["outdegree"] >= 1.0


def test_per_task_costs_are_the_same_on_every_node():
    dag = random_dag(random.Random(2), ["a", "b", "c"], n=30, cost_model="per-task")
    assert all(len(set(t.cost.values())) == 1 for t in dag.tasks.values())
    with pytest.raises(ValueError, match="unknown cost model"):
        random_dag(random.Random(2), ["a"], cost_model="other")


def test_cluster_is_a_full_mesh_of_two_cpu_nodes():
    p = random_cluster(random.Random(3))
    assert [x.cores for x in p.processors] == [2] * 6
    assert len(p.links) == 15
    assert all(0.5 <= link.bandwidth <= 1.0 for link in p.links)  # 500..1000 Mbit/s in Mbit per ms


def test_critical_path_uses_mean_costs():
    from continuum.engine import TaskGraph

    dag = TaskGraph.from_dict(
        {
            "tasks": [
                {"id": "a", "cost": {"x": 2, "y": 4}},
                {"id": "b", "cost": {"x": 10}},
                {"id": "c", "cost": {"x": 1}},
            ],
            "edges": [{"src": "a", "dst": "b", "data": 5}, {"src": "a", "dst": "c"}],
        }
    )
    assert critical_path_length(dag) == 13


def test_corpus_statistics_near_table_4_28():
    rng = random.Random(0)
    stats = corpus_stats(random_dag(rng, [f"n{i}" for i in range(6)]) for _ in range(150))
    assert stats["nodes"]["avg"] == pytest.approx(181.8, rel=0.15)
    assert stats["nodes"]["median"] == pytest.approx(130, rel=0.2)
    assert stats["outdegree"]["avg"] == pytest.approx(1.4, rel=0.15)
    assert stats["critical_path_ms"]["median"] == pytest.approx(41, rel=0.2)
    assert stats["task_cost_ms"]["min"] == 1 and stats["task_cost_ms"]["max"] == 20
