"""The three formulations of the monitor MILP (Eqs. 3.21-3.22) against brute force on small instances.

Every formulation must reach the brute-force optimum (minimum total overload first, then minimum delay),
and every valid inequality of the strengthened models (spread cuts, relief and host covers) must hold
for every capacity-feasible allocation: the cuts may tighten the LP relaxation, never remove a solution.
"""

import itertools
import math
import random

import numpy as np
import pytest

from continuum.engine.core.errors import InputError
from continuum.engine.verification import monitor_milp
from continuum.engine.verification.monitor_milp import (
    FORMULATIONS,
    MonitorStats,
    _build,
    _classes,
    _host_covers,
    _relief_covers,
    _vector,
    allocate,
    complete_cpu,
)


def _instance(seed: int) -> dict:
    """3-4 units; two or three "robots" publishing 2-3 topics each; 5-7 monitors reading 1-2 topics of
    one robot and sometimes one of another (cross-robot reads); few distinct CPU values so that monitors
    form classes; capacities drawn around the total load, so that some instances are tight, some need a
    slow unit to host the overflow (host covers) and some are infeasible (overloaded)."""
    rng = random.Random(seed)
    n_units = rng.choice([3, 4])
    units = [f"u{j}" for j in range(n_units)]
    n_robots = rng.choice([2, 3])
    topics, by_robot = [], {}
    for r in range(n_robots):
        for t in range(rng.choice([2, 3])):
            name = f"/r{r}/t{t}"
            by_robot.setdefault(r, []).append(name)
            topics.append(
                {
                    "name": name,
                    # integer delays: the ε migration term (≤ 7e-3 here) can never outweigh a delay difference
                    "delay": {u: (0 if j == r else rng.choice([5, 10, 20, 100])) for j, u in enumerate(units)},
                    "cpu": {u: (0.0 if j == r else rng.choice([0.0, 0.5, 1.0])) for j, u in enumerate(units)},
                }
            )
    monitors = []
    for i in range(rng.randint(5, 7)):
        r = rng.randrange(n_robots)
        reads = rng.sample(by_robot[r], rng.randint(1, min(2, len(by_robot[r]))))
        if rng.random() < 0.4:
            other = rng.choice([o for o in range(n_robots) if o != r])
            reads.append(rng.choice(by_robot[other]))
        base = rng.choice([2.0, 3.0, 5.0])
        monitors.append(
            {
                "name": f"m{i}",
                "topics": reads,
                "cpu": {u: base * (1.0 if j < n_robots else rng.choice([0.5, 1.0])) for j, u in enumerate(units)},
                "current": units[min(r, n_units - 1)],
            }
        )
    total = sum(m["cpu"][m["current"]] for m in monitors)
    scale = rng.uniform(0.35, 0.9)
    nodes = [{"name": u, "available_cpu": round(min(100.0, total * scale * rng.uniform(0.3, 1.0)), 1)} for u in units]
    return {"format": "continuum.monitorstats/v1", "nodes": nodes, "topics": topics, "monitors": monitors}


def _brute_force(stats: MonitorStats):
    """(minimum total overload, minimum delay among those, feasible allocations as dicts)."""
    cpu = complete_cpu(stats)
    cap = stats.capacity()
    best = None
    feasible = []
    for choice in itertools.product(range(len(stats.nodes)), repeat=len(stats.monitors)):
        load = [0.0] * len(stats.nodes)
        received: set[tuple[str, int]] = set()
        for a, b in enumerate(choice):
            load[b] += cpu[a, b]
            received.update((k, b) for k in stats.monitor_topics[stats.monitors[a]])
        delay = 0.0
        for k, b in received:
            load[b] += stats.topic_cpu[k].get(stats.nodes[b], 0.0)
            delay += stats.delay[k][stats.nodes[b]]
        excess = sum(max(0.0, load[b] - cap[j]) for b, j in enumerate(stats.nodes))
        key = (round(excess, 6), round(delay, 6))
        if best is None or key < best:
            best = key
        if excess <= 1e-9:
            feasible.append({stats.monitors[a]: stats.nodes[b] for a, b in enumerate(choice)})
    return best[0], best[1], feasible


SEEDS = range(40)


@pytest.mark.parametrize("seed", SEEDS)
def test_every_formulation_reaches_the_brute_force_optimum(seed):
    stats = MonitorStats.from_dict(_instance(seed))
    excess, delay, feasible = _brute_force(stats)
    for formulation in FORMULATIONS:
        result = allocate(stats, formulation=formulation, mip_rel_gap=0.0, time_limit=60.0)
        assert result.status in ("optimal", "overloaded"), (formulation, result.status)
        assert result.feasible == (excess == 0), formulation
        assert set(result.allocation) == set(stats.monitors)
        total_over = sum(max(0.0, result.cpu[j] - result.capacity[j]) for j in stats.nodes)
        assert total_over == pytest.approx(excess, abs=1e-6), formulation
        assert result.objective == pytest.approx(delay, abs=1e-6), formulation
        if result.feasible:  # the returned allocation is one of the capacity-feasible ones
            assert result.allocation in feasible


@pytest.mark.parametrize("seed", SEEDS)
def test_the_seed_searches_keep_the_brute_force_optimum(seed, monkeypatch):
    """These instances are below SEED_SEARCH_PAIRS, so allocate() skips the robot-level seed and the
    neighbourhood step on them; forced on, the optimum is the same."""
    monkeypatch.setattr(monitor_milp, "SEED_SEARCH_PAIRS", 0)
    stats = MonitorStats.from_dict(_instance(seed))
    excess, delay, _ = _brute_force(stats)
    result = allocate(stats, mip_rel_gap=0.0, time_limit=60.0)
    assert result.status in ("optimal", "overloaded")
    total_over = sum(max(0.0, result.cpu[j] - result.capacity[j]) for j in stats.nodes)
    assert total_over == pytest.approx(excess, abs=1e-6)
    assert result.objective == pytest.approx(delay, abs=1e-6)


def _local(edge_available: float, desktop_delay: float) -> dict:
    """Thesis case study 1 in small: 6 monitors on the edge reading its two topics (delay 0 there)."""
    nodes = [{"name": "edge", "available_cpu": edge_available}, {"name": "desktop", "available_cpu": 100.0}]
    topics = [{"name": f"/t{k}", "delay": {"edge": 1.0, "desktop": desktop_delay}, "cpu": {"desktop": 0.2}}
              for k in range(2)]  # fmt: skip
    monitors = [{"name": f"m{i}", "topics": [f"/t{i % 2}"], "cpu": {"edge": 5.0, "desktop": 2.0}, "current": "edge"}
                for i in range(6)]  # fmt: skip
    return {"format": "continuum.monitorstats/v1", "nodes": nodes, "topics": topics, "monitors": monitors}


def test_an_allocation_at_the_trivial_bound_is_answered_without_a_solver():
    """Everything fits where it runs and every topic arrives soonest there: optimal as it is, no solver run
    (no branch-and-bound node, no bound); brute force agrees."""
    stats = MonitorStats.from_dict(_local(100.0, 10.0))
    result = allocate(stats)
    assert (result.status, result.migrations, result.objective) == ("optimal", [], 2.0)
    assert result.nodes == 0 and result.root_bound == -math.inf
    assert _brute_force(stats)[:2] == (0.0, 2.0)


@pytest.mark.parametrize("edge_available, desktop_delay", [(100.0, 0.5), (20.0, 10.0)])
def test_an_allocation_above_the_trivial_bound_is_still_solved(edge_available, desktop_delay):
    """The topics arrive sooner on the desktop, or the edge has no room for every monitor: the solver
    decides, and reaches the brute-force optimum."""
    stats = MonitorStats.from_dict(_local(edge_available, desktop_delay))
    excess, delay, _ = _brute_force(stats)
    result = allocate(stats, mip_rel_gap=0.0)
    assert result.status == "optimal" and result.migrations
    assert excess == 0 and result.objective == pytest.approx(delay)
    assert result.root_bound > -math.inf


@pytest.mark.parametrize("seed", SEEDS)
def test_the_cuts_keep_every_feasible_allocation(seed):
    """Every capacity-feasible allocation, written in the variables of the strengthened model (with the
    cover choice variables set as in the validity argument), satisfies every row: no cut is invalid."""
    stats = MonitorStats.from_dict(_instance(seed))
    _, _, feasible = _brute_force(stats)
    cpu = complete_cpu(stats)
    cl = _classes(stats, cpu, False)
    model = _build(stats, cl, 1e-3, slack=False, formulation="covers")
    for placement in feasible:
        x = _vector(model, stats, cl, placement)
        for fam in model.families:  # _vector found the cover set the argument names
            assert x[fam.w0 : fam.w0 + len(fam.sets)].sum() == pytest.approx(1.0)
        ax = model.a @ x
        assert np.all(ax >= model.lo - 1e-7) and np.all(ax <= model.hi + 1e-7)
        assert np.all(x <= model.ub + 1e-9)


def test_the_instances_exercise_the_covers():
    """The random instances above are not all trivial: some have relief covers, some host covers."""
    relief = host = infeasible = 0
    for seed in SEEDS:
        stats = MonitorStats.from_dict(_instance(seed))
        cl = _classes(stats, complete_cpu(stats), False)
        fams, cuts = _relief_covers(stats, cl)
        relief += bool(fams or cuts)
        fams, cuts = _host_covers(stats, cl)
        host += bool(fams or cuts)
        infeasible += _brute_force(stats)[0] > 0
    assert relief >= 5 and host >= 3 and infeasible >= 3 and infeasible <= len(SEEDS) - 10


def test_unknown_formulation_is_an_input_error():
    stats = MonitorStats.from_dict(_instance(0))
    with pytest.raises(InputError) as err:
        allocate(stats, formulation="dantzig")
    assert err.value.field == "formulation"
