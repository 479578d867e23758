"""The schedulers HEFT4K is compared with: default Kubernetes model, HEFT on Kubernetes, ideal HEFT, DPE."""

import random
from collections import Counter

import pytest

from continuum.engine import InputError, Platform, TaskGraph
from continuum.engine.heft4k.k8s_baselines import (
    Unschedulable,
    compare,
    dpe,
    k8s_default_placement,
    pod_capacities,
    speedup,
)

from .test_heft4k import random_cluster, random_dag


def six_by_two():
    return Platform.from_dict({"processors": [{"id": f"n{i}", "cores": 2} for i in range(6)], "bandwidth": 0.75})


def chain(n):
    return TaskGraph.from_dict(
        {
            "tasks": [{"id": f"t{i}", "cost": {"cpu": 1}} for i in range(n)],
            "edges": [{"src": f"t{i}", "dst": f"t{i + 1}", "data": 1.0} for i in range(n - 1)],
        }
    )


def test_speedup_definition_matches_the_thesis_example():
    assert round(speedup(14.7, 11.0), 1) == 33.6
    assert round(speedup(13.3, 11.0), 1) == 20.9
    assert round(speedup(14.7, 13.3), 1) == 10.5
    with pytest.raises(InputError):
        speedup(1.0, 0.0)


def test_pod_capacity_of_the_thesis_cluster():
    assert list(pod_capacities(six_by_two()).values()) == [27, 27, 27, 27, 26, 26]
    mixed = Platform.from_dict({"processors": [{"id": "big", "cores": 4}, {"id": "small", "cores": 1}]})
    assert pod_capacities(mixed, 10) == {"big": 8, "small": 2}


def test_default_kubernetes_fails_above_160_pods():
    platform = six_by_two()
    placement = k8s_default_placement(chain(160), platform)
    assert Counter(placement.values()) == Counter({"n0": 27, "n1": 27, "n2": 27, "n3": 27, "n4": 26, "n5": 26})
    with pytest.raises(Unschedulable, match="pod 't160' fits no node") as err:
        k8s_default_placement(chain(170), platform)
    assert err.value.pending[0] == "t160" and len(err.value.pending) == 10


def test_default_kubernetes_spreads_and_is_seeded():
    platform = six_by_two()
    a = k8s_default_placement(chain(30), platform, seed=1)
    assert a == k8s_default_placement(chain(30), platform, seed=1)
    assert max(Counter(a.values()).values()) - min(Counter(a.values()).values()) <= 1  # least allocated
    assert any(k8s_default_placement(chain(30), platform, seed=s) != a for s in range(2, 6))


def test_default_kubernetes_skips_nodes_without_an_implementation():
    dag = TaskGraph.from_dict({"tasks": [{"id": f"g{i}", "cost": {"gpu": 1}} for i in range(4)], "edges": []})
    platform = Platform.from_dict({"processors": [{"id": "c", "class": "cpu"}, {"id": "g", "class": "gpu"}]})
    assert set(k8s_default_placement(dag, platform).values()) == {"g"}


@pytest.mark.parametrize("seed", range(10))
def test_dpe_plans_are_valid(seed):
    rng = random.Random(300 + seed)
    nodes = [f"n{i}" for i in range(rng.randint(2, 5))]
    dag = random_dag(rng, rng.randint(2, 50), nodes)
    platform = random_cluster(rng, nodes)
    s = dpe(dag, platform)
    assert s.violations(dag, platform) == []


def test_dpe_keeps_a_heavy_pair_together():
    dag = TaskGraph.from_dict(
        {
            "tasks": [{"id": "a", "cost": {"n1": 2, "n2": 1}}, {"id": "b", "cost": {"n1": 1, "n2": 3}}],
            "edges": [{"src": "a", "dst": "b", "data": 10.0}],
        }
    )
    platform = Platform.from_dict({"processors": [{"id": "n1"}, {"id": "n2"}], "bandwidth": 1.0})
    s = dpe(dag, platform)
    assert {a.task: a.processor for a in s.assignments} == {"a": "n1", "b": "n1"}
    assert s.makespan == 3


def test_compare_runs_every_scheduler_in_one_simulator():
    rng = random.Random(9)
    nodes = [f"n{i}" for i in range(3)]
    dag = random_dag(rng, 25, nodes)
    platform = random_cluster(rng, nodes, max_cores=2)
    out = compare(dag, platform, seed=3)
    assert set(out) == {"k8s-default", "heft-k8s", "heft4k", "heft-ideal", "dpe"}
    assert out["heft4k"].params["simulator"] == "cfs-fluid"
    # Same mapping, only the niceness differs.
    assert {a.task: a.processor for a in out["heft4k"].assignments} == {
        a.task: a.processor for a in out["heft-k8s"].assignments
    }
    assert {a.niceness for a in out["heft-k8s"].assignments} == {0}
    assert len({a.niceness for a in out["heft4k"].assignments}) > 1
    too_big = compare(chain(200), six_by_two())
    assert too_big["k8s-default"] is None and too_big["heft4k"].makespan > 0
