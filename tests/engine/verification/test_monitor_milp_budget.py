"""A budget in work (branch-and-bound nodes) instead of seconds: the same inputs give the same allocation,
whatever the machine's load, and the case-study simulations are reproducible from their seed."""

import math

from benchmarks.milp_scaling import fleet
from continuum.engine.verification.abv_simulation import kairos_scenario, simulate, synthetic_scenario
from continuum.engine.verification.monitor_milp import MonitorStats, allocate


def test_a_node_budget_stops_the_search_at_the_same_allocation_every_time():
    # Cross-robot reads tie the fleet into one block whose root node does not close: one node of budget
    # stops the search with a gap, at the same incumbent on every run.
    stats = MonitorStats.from_dict(fleet(300, 15, seed=4, uniform=False, cross=0.1))
    runs = [allocate(stats, time_limit=math.inf, work_limit=1) for _ in range(2)]
    assert runs[0].status == "time_limit" and runs[0].gap > 0
    assert runs[1].allocation == runs[0].allocation
    assert (runs[1].objective, runs[1].gap, runs[1].status) == (runs[0].objective, runs[0].gap, runs[0].status)


def test_an_unbounded_budget_matches_the_time_limited_optimum_on_a_small_fleet():
    stats = MonitorStats.from_dict(fleet(60, 5, seed=1, uniform=True, cross=0.1))
    by_work = allocate(stats, time_limit=math.inf, work_limit=10**6)
    by_time = allocate(stats, time_limit=30.0)
    assert by_work.status == by_time.status == "optimal"
    assert math.isclose(by_work.objective, by_time.objective, rel_tol=1e-4)


def _trace(result):
    """What a simulation decided, without the measured solve times."""
    periods = []
    for p in result.periods:
        alloc = dict(p.allocation or {})
        alloc.pop("solve_time_ms", None)
        periods.append((p.t, p.monitors, p.dropped, alloc))
    return periods, [(m.t, m.monitor, m.source, m.target, m.events_moved) for m in result.migrations], result.placement


def test_the_case_study_simulations_are_reproducible_from_their_seed():
    scenarios = (
        lambda: synthetic_scenario(duration_s=40.0, seed=5, noise=3.0),
        lambda: kairos_scenario(duration_s=20.0, seed=5),
    )
    for make in scenarios:
        first, second = simulate(make()), simulate(make())
        assert _trace(first) == _trace(second)
