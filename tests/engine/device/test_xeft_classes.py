"""XEFT against HEFT on the generated Tree/Linear classes (issue 27): the generator checked against spec 01
section 8.2, Algorithm 1's clusters checked row by row, and the thesis' claim measured.

What this shows: Algorithm 1 (rows 6-33, the row-30 reading of spec 01 section 4.1) and APPLY do what the thesis
prints, and the generator draws what spec 01 section 8.2 proposes; yet on these classes XEFT does not beat HEFT on
average: within about +-1 % of HEFT in both classes (seeds 0-199: -0.9 % Tree, -0.7 % Linear; seeds 0-99:
Linear +0.3 %), winning on fewer DAGs than it loses, with HEFT's insertion already filling many of the idle gaps
XEFT's clusters aim at. The thesis' qualitative reading of Fig. 4.1 holds: on Tree DAGs XEFT gains where HEFT's
exclusive-overlap efficiency is below 80 % and loses where it is above. On the authors' own ORB-SLAM graph XEFT
beats HEFT at 2-5 cores.
"""

import statistics
from pathlib import Path

import pytest

from continuum.engine.device.board import board
from continuum.engine.device.generators import thesis_dag
from continuum.engine.device.heft import compile_problem, compiled_ranks, heft, priority_list
from continuum.engine.device.overlap import schedule_metrics
from continuum.engine.device.xeft import build_cluster, class_times, descendants, xeft
from continuum.engine.formats import load_dag

DATA = Path(__file__).resolve().parents[2] / "data"
SEEDS = range(100)
RANKS = {"rank_mode": "max", "comm_mode": "impl"}


@pytest.fixture(scope="module")
def runs():
    out = []
    for seed in SEEDS:
        dag = thesis_dag(seed)
        plat = board(2 + seed % 4)
        h = heft(dag, plat, **RANKS)
        x = xeft(dag, plat, **RANKS)
        out.append((dag, plat, h, x))
    return out


def test_generator_draws_spec_01_section_8_2(runs):
    fractions, cpu_only = [], []
    for dag, _, _, _ in runs:
        assert 20 <= len(dag) <= 250
        exclusive = [t for t in dag.tasks.values() if len(t.cost) == 1]
        fractions.append(len(exclusive) / len(dag))
        cpu_only += ["cpu" in t.cost for t in exclusive]
        for t in dag.tasks.values():
            assert all(1 <= v <= 20 for k, v in t.cost.items() if k == "cpu")
    assert 0.25 < statistics.mean(fractions) < 0.35  # Normal(0.30, 0.15) clipped
    assert 0.45 < statistics.mean(cpu_only) < 0.55  # CPU-only with p = 0.5
    classes = [dag.meta["class"] for dag, _, _, _ in runs]
    assert 30 < classes.count("tree") < 70


def test_algorithm_1_clusters_row_by_row(runs):
    for dag, plat, _, _ in runs[:40]:
        prob = compile_problem(dag, plat)
        order = priority_list(prob, compiled_ranks(prob, "max", "impl"))
        trace: list[dict] = []
        new = build_cluster(prob, order, trace=trace)
        desc = descendants(prob)
        where = {t: i for i, t in enumerate(new)}
        assert sorted(new) == sorted(order)
        for t in range(prob.n):  # still a topological order
            assert all(where[q] > where[t] for q, _ in prob.succ[t])
        cpu, gpu = class_times(prob, "cpu"), class_times(prob, "gpu")
        n_cores = sum(1 for p in plat.processors if p.cls == "cpu")
        for step in trace:
            cand, cluster = step["candidates"], step["cluster"]
            # row 9: no path between any two candidates
            assert all(not (desc[a] >> b & 1) for a in cand for b in cand if a != b)
            g_only = [c for c in cand if cpu[c] is None]
            c_only = [c for c in cand if gpu[c] is None]
            # rows 18-19 / 26-27: the shorter side's nodes all join; the other side's only while they balance
            if step["total_gpu"] < step["total_cpu"] / n_cores:
                assert set(g_only) <= set(cluster)
            else:
                assert set(c_only) <= set(cluster)
            assert set(cluster) <= set(cand)
            # APPLY: the cluster ends up contiguous in the final list only if no later cluster moved into it;
            # right after its own APPLY it is contiguous.
            final = step["steps"][-1] if step["steps"] else None
            if final is not None:
                pos = sorted(final.index(c) for c in cluster)
                assert pos == list(range(pos[0], pos[0] + len(cluster)))


def gains_by_class(runs):
    out: dict[str, list[tuple[float, float]]] = {"tree": [], "linear": []}
    for dag, plat, h, x in runs:
        eff = schedule_metrics(h, dag, plat)["xo_efficiency"] or 0.0
        out[dag.meta["class"]].append((eff, (h.makespan - x.makespan) / h.makespan))
    return out


def test_the_thesis_claim_does_not_hold_on_average_on_these_classes(runs):
    by_class = gains_by_class(runs)
    for cls, pairs in by_class.items():
        gains = [g for _, g in pairs]
        assert statistics.mean(gains) < 0.01, cls  # no better than HEFT by even 1 % on average
        assert any(g > 0 for g in gains) and any(g < 0 for g in gains), cls  # it wins on some, loses on others
        assert sum(g > 1e-9 for g in gains) < 0.6 * len(gains), cls  # and wins on no clear majority
    assert statistics.mean(g for _, g in by_class["tree"]) < 0


def test_fig_4_1_tree_xeft_gains_below_80_percent_xo_efficiency_and_loses_above(runs):
    tree = gains_by_class(runs)["tree"]
    low = [g for eff, g in tree if eff < 0.8]
    high = [g for eff, g in tree if eff >= 0.8]
    assert low and high
    assert statistics.mean(low) > statistics.mean(high)
    assert statistics.mean(high) < 0


@pytest.mark.parametrize("cores", [2, 3, 4, 5])
def test_xeft_beats_heft_on_the_authors_orb_graph(cores):
    dag = load_dag((DATA / "orb_graph.csv").read_bytes())
    plat = board(cores)
    assert xeft(dag, plat, **RANKS).makespan < heft(dag, plat, **RANKS).makespan
