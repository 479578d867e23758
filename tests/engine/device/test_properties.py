"""Property tests on generated DAGs (spec 01 acceptance 9-14): every algorithm, one frame and several,
gives only valid schedules; XEFT lists are topological with contiguous, pairwise unreachable clusters;
XO(A) <= O(A) and <= Max_XO; buffers_used <= frames."""

import logging
import random

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from continuum.engine import Platform, Processor
from continuum.engine.device import overlap as ov
from continuum.engine.device.algorithms import SCHEDULERS
from continuum.engine.device.board import board
from continuum.engine.device.generators import classify, layered_dag, related_platform, thesis_dag
from continuum.engine.device.heft import compile_problem, compiled_ranks, heft, priority_list
from continuum.engine.device.pipeline import NATIVE, frame_violations, pipeline, releases, replicate
from continuum.engine.device.xeft import build_cluster, descendants

log = logging.getLogger(__name__)
# The device-level schedulers with a native multi-frame form (HEFT4K is a cluster-level mapper).
ALGORITHMS = sorted(NATIVE)
SEEDS = range(500)


def case(seed: int):
    """A generated CPU/GPU DAG (20-100 nodes, transfers half the time) and a board of 1-5 cores."""
    rng = random.Random(seed)
    dag = thesis_dag(seed, n=rng.randint(20, 100), transfer=(0.0, 2.0) if rng.random() < 0.5 else None)
    cores = rng.randint(1, 5)
    speeds = [rng.choice([1.0, 1.0, 1.5]) for _ in range(cores)] if rng.random() < 0.3 else None
    return dag, board(cores, cpu_speed=speeds)


@pytest.mark.parametrize("chunk", range(5))
def test_single_frame_schedules_are_valid(chunk):
    for seed in SEEDS[chunk::5]:
        dag, platform = case(seed)
        for name in sorted(SCHEDULERS):
            s = SCHEDULERS[name](dag, platform)
            assert s.violations(dag, platform) == [], (seed, name)
            assert {a.frame for a in s.assignments} == {0}
            o, xo = ov.overlap(s), ov.exclusive_overlap(s, dag, platform)
            assert xo <= o + 1e-6 and xo <= ov.max_xo(dag, platform) + 1e-6, (seed, name)
            assert ov.buffers_used(s) == 1


@pytest.mark.parametrize("chunk", range(5))
def test_xeft_lists(chunk):
    for seed in SEEDS[chunk::5]:
        dag, platform = case(seed)
        prob = compile_problem(dag, platform)
        base = priority_list(prob, compiled_ranks(prob, "max", "impl"))
        trace: list[dict] = []
        order = build_cluster(prob, base, trace=trace)
        assert sorted(order) == list(range(prob.n))
        where = {t: i for i, t in enumerate(order)}
        assert all(where[s] < where[d] for d in range(prob.n) for s, _ in prob.pred[d]), seed  # topological
        desc = descendants(prob)
        for step in trace:
            for lst in step["steps"]:  # every intermediate APPLY list stays topological too
                pos = {t: i for i, t in enumerate(lst)}
                assert all(pos[s] < pos[d] for d in range(prob.n) for s, _ in prob.pred[d])
            cluster = step["cluster"]
            for a in cluster:
                assert not any(desc[a] >> b & 1 for b in cluster), seed  # pairwise unreachable
        if trace:  # the last cluster formed is contiguous in the final list
            positions = sorted(where[t] for t in trace[-1]["cluster"])
            assert positions == list(range(positions[0], positions[0] + len(positions))), seed


@pytest.mark.parametrize("chunk", range(4))
def test_multi_frame_schedules_are_valid(chunk):
    for seed in range(chunk, 200, 4):
        dag, platform = case(seed)
        rng = random.Random(seed)
        frames = rng.randint(2, 4)
        release = releases(frames, period=rng.choice([None, 10.0, 40.0]), batch=rng.choice([None, 2]))
        for name in ALGORITHMS:
            s = NATIVE[name](dag, platform, release)
            assert s.violations(dag, platform) == [], (seed, name)
            assert frame_violations(s, dag, release) == [], (seed, name)
            assert sorted({a.frame for a in s.assignments}) == list(range(frames))
            assert ov.buffers_used(s) <= frames


def test_batched_not_worse_than_streaming():
    """Acceptance 14: batched makespan <= streaming makespan, up to list-scheduling anomalies (logged).

    Finding: with the camera period at half the single-frame HEFT makespan (the thesis' regime: 33 ms
    frames for a DAG of about 70 ms), 2-3.5 % of the DAGs are anomalous for HEFT, XEFT and G-FL_c (measured
    on 200 seeds; about 0 % for HEFT/XEFT at a period equal to the makespan), above the spec's 1 % guess:
    a greedy list scheduler that may start later frames earlier fills gaps that a later task needed. The
    bound below guards against a regression, not against anomalies.
    """
    worse = dict.fromkeys(ALGORITHMS, 0)
    seeds = range(1000, 1150)
    for seed in seeds:
        dag, platform = case(seed)
        frames = random.Random(seed).choice([3, 5])
        period = heft(dag, platform).makespan / 2
        for name in ALGORITHMS:
            streaming = NATIVE[name](dag, platform, releases(frames, period=period)).makespan
            batched = NATIVE[name](dag, platform, releases(frames)).makespan
            if batched > streaming + 1e-9:
                worse[name] += 1
                log.warning("batched %s > streaming %s: seed %s %s", batched, streaming, seed, name)
    assert all(count <= len(seeds) * 5 // 100 for count in worse.values()), worse
    assert worse["visionworks"] == worse["visionworks_overlap"] == 0


def test_generic_replication_for_an_unregistered_scheduler():
    dag, platform = case(7)
    single = heft(dag, platform)
    rel = releases(3, period=5.0)
    frames = replicate(single, rel)
    s = type(single)("custom", frames)
    assert s.violations(dag, platform) == [] and frame_violations(s, dag, rel) == []


def test_pipeline_through_run_for_every_algorithm():
    dag, platform = case(11)
    for name in ALGORITHMS:
        s = pipeline(name, dag, platform, frames=3)
        assert s.metrics["buffers_used"] <= 3 and s.metrics["frames"] == 3
        assert s.metrics["single_frame_makespan"] * 3 >= s.makespan - 1e-9 or name.startswith("visionworks")


def test_generator_is_seeded_and_classifies():
    assert thesis_dag(5).to_dict() == thesis_dag(5).to_dict()
    assert thesis_dag(5).to_dict() != thesis_dag(6).to_dict()
    shapes = [thesis_dag(s) for s in range(40)]
    assert all(20 <= len(d) <= 250 for d in shapes)
    assert all(d.meta["class"] == classify(d) for d in shapes)
    assert {d.meta["class"] for d in shapes} == {"tree", "linear"}
    assert all(d.meta["class"] == d.meta["shape"] for d in shapes)
    big = layered_dag(2000, seed=3, ccr=2.0)
    mean_cost = sum(t.cost["cpu"] for t in big.tasks.values()) / len(big)
    mean_data = sum(e.data for e in big.edges) / len(big.edges)
    assert 1.6 < mean_data / mean_cost < 2.4  # the CCR is met on average


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    n=st.integers(1, 60),
    seed=st.integers(0, 10_000),
    procs=st.integers(1, 6),
    comm=st.sampled_from(["free", "uniform", "general"]),
    unrelated=st.booleans(),
    insertion=st.booleans(),
    frames=st.integers(1, 3),
)
def test_rank_based_on_heterogeneous_platforms(n, seed, procs, comm, unrelated, insertion, frames):
    """HEFT/XEFT's three ready-time paths (free, uniform, per-link transfers) all give valid schedules."""
    dag = layered_dag(n, seed=seed, processors=procs if unrelated else None, heterogeneity=1.0)
    rng = random.Random(seed)
    bandwidth = None if comm == "free" else 2.0
    if unrelated:
        platform = Platform([Processor(f"p{j}", "cpu") for j in range(procs)], bandwidth=bandwidth)
    else:
        platform = related_platform(procs, seed=seed, bandwidth=bandwidth)
    if comm == "general" and procs > 1:
        doc = platform.to_dict()
        ids = [p["id"] for p in doc["processors"]]
        doc["links"] = [
            {"src": a, "dst": b, "bandwidth": rng.choice([None, 0.5, 4.0]), "latency": rng.random()}
            for i, a in enumerate(ids)
            for b in ids[i + 1 :]
            if rng.random() < 0.7
        ]
        platform = Platform.from_dict(doc)
    release = releases(frames, period=rng.choice([None, 20.0]))
    for name in ("heft", "xeft"):
        s = NATIVE[name](dag, platform, release, insertion=insertion)
        assert s.violations(dag, platform) == []
        assert frame_violations(s, dag, release) == []


@pytest.mark.parametrize("seed", range(4))
def test_numpy_ready_times_match_the_scalar_path(seed, monkeypatch):
    import continuum.engine.device.heft as heft_module

    rng = random.Random(seed)
    dag = layered_dag(120, seed=seed)
    doc = related_platform(12, seed=seed).to_dict()
    ids = [p["id"] for p in doc["processors"]]
    doc["links"] = [
        {"src": a, "dst": b, "bandwidth": rng.choice([None, 0.5, 2.0]), "latency": rng.random()}
        for i, a in enumerate(ids)
        for b in ids[i + 1 :]
        if rng.random() < 0.8
    ]
    platform = Platform.from_dict(doc)
    monkeypatch.setattr(heft_module, "VECTOR_FROM", 10**9)
    scalar = heft_module.heft(dag, platform).to_dict()
    monkeypatch.setattr(heft_module, "VECTOR_FROM", 1)
    assert heft_module.heft(dag, platform).to_dict() == scalar
