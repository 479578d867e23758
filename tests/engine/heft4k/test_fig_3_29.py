"""Thesis Figs. 3.29/3.30: the same DAG under default Kubernetes, ideal HEFT, HEFT on Kubernetes and HEFT4K.

The thesis prints only the makespans (14.7, 11, 13.3 ms; HEFT4K +20.9% over HEFT on Kubernetes, +33.6% over
Kubernetes) and the critical path A -> F -> G; the DAG in ``tests/data/fig-3.29.*`` is a reconstruction
(found by ``benchmarks/fig329_search.py``) whose simulated executions give those numbers. Thesis scenario: the
DAG was searched for to give the four makespans, so matching them reproduces nothing.
"""

import json
from pathlib import Path

import pytest

from continuum.engine import TaskGraph
from continuum.engine.core.cluster import cluster_platform
from continuum.engine.heft4k.heft4k import heft4k
from continuum.engine.heft4k.k8s_baselines import run_heft4k, run_heft_k8s, run_k8s_default, speedup

DATA = Path(__file__).resolve().parents[2] / "data"
#: The default-Kubernetes tie-break seed of the reconstruction (kube-scheduler picks ties at random).
K8S_SEED = 1


@pytest.fixture(scope="module")
def example():
    dag = TaskGraph.from_dict(json.loads((DATA / "fig-3.29.dag.json").read_text()))
    platform = cluster_platform(json.loads((DATA / "fig-3.29.cluster.json").read_text()))
    plan = heft4k(dag, platform)
    return (
        dag,
        platform,
        plan,
        {
            "k8s": run_k8s_default(dag, platform, seed=K8S_SEED, trace=True),
            "heft-k8s": run_heft_k8s(dag, platform, plan, trace=True),
            "heft4k": run_heft4k(dag, platform, plan, trace=True),
        },
    )


def test_ideal_heft_plan_and_its_critical_path(example):
    dag, platform, plan, _ = example
    assert plan.makespan == 11.0
    assert [t for t, _ in plan.critical_path(dag, platform)] == ["A", "F", "G"]
    assert plan.violations(dag, platform) == []


def test_simulated_makespans_are_the_thesis_figures(example):
    _, _, _, runs = example
    assert round(runs["k8s"].makespan, 1) == 14.7
    assert round(runs["heft-k8s"].makespan, 1) == 13.3
    assert round(runs["heft4k"].makespan, 1) == 11.0
    assert round(speedup(runs["heft-k8s"].makespan, runs["heft4k"].makespan), 1) == 21.2  # thesis: 20.9 from 13.3/11
    assert round(speedup(13.3, 11.0), 1) == 20.9 and round(speedup(14.7, 11.0), 1) == 33.6
    assert round(speedup(runs["k8s"].makespan, runs["heft4k"].makespan), 1) == 33.3


def test_niceness_removes_the_inversion_around_f(example):
    _, _, _, runs = example
    f_shared = runs["heft-k8s"].metrics["segments"]["F"]
    f_nice = runs["heft4k"].metrics["segments"]["F"]
    assert [rate for _, _, rate in f_shared] == pytest.approx([2 / 3, 1 / 2])  # F shares N2 with C, H, then D
    assert f_nice == [[3.0, 6.0, 1.0]]  # with niceness F runs as planned
    assert runs["heft4k"].metrics["priority_inversion_cpu"] < runs["heft-k8s"].metrics["priority_inversion_cpu"] / 5
    assert runs["heft4k"].metrics["preemptions"] < runs["heft-k8s"].metrics["preemptions"]
