"""Monitor allocation MILP (Eqs. 3.21-3.22, spec 03 §10, acceptance check 14) against brute force."""

import itertools
import random

import pytest

from continuum.engine.core.errors import InputError
from continuum.engine.verification.monitor_milp import (
    MonitorAllocator,
    MonitorStats,
    StatsFilter,
    allocate,
    complete_cpu,
)


def _doc(nodes, topics, monitors):
    return {"format": "continuum.monitorstats/v1", "nodes": nodes, "topics": topics, "monitors": monitors}


def _case_study_1(edge_available=100.0, n=50):
    """Spec 03 §13.1/§14: 50 monitors over 5 topics published on edge; edge, desktop (10 ms), server (100 ms)."""
    nodes = [
        {"name": "edge", "available_cpu": edge_available},
        {"name": "desktop", "available_cpu": 100.0},
        {"name": "server", "available_cpu": 100.0},
    ]
    topics = [
        {"name": f"/t{k}", "delay": {"edge": 0.0, "desktop": 10.0, "server": 100.0},
         "cpu": {"edge": 0.0, "desktop": 0.2, "server": 0.2}}
        for k in range(5)
    ]  # fmt: skip
    monitors = [
        {"name": f"m{i}", "topics": [f"/t{i % 5}", f"/t{(i + 1) % 5}"],
         "cpu": {"edge": 0.76, "desktop": 0.5, "server": 0.36}, "current": "edge"}
        for i in range(n)
    ]  # fmt: skip
    return _doc(nodes, topics, monitors)


def test_unlimited_capacity_keeps_monitors_with_their_data():
    result = allocate(_case_study_1())
    assert result.feasible and result.status == "optimal"
    assert set(result.allocation.values()) == {"edge"}
    assert result.objective == 0 and result.migrations == []
    assert result.cpu["edge"] == pytest.approx(50 * 0.76)


def test_saturated_edge_moves_monitors_to_the_nearest_unit():
    # edge has 20 % available: 26 monitors fit (26 x 0.76 = 19.76); the others go to desktop (10 ms)
    result = allocate(_case_study_1(edge_available=20.0))
    assert result.feasible
    on = {j: sum(1 for v in result.allocation.values() if v == j) for j in ("edge", "desktop", "server")}
    assert on["server"] == 0 and on["edge"] <= 26 and on["edge"] + on["desktop"] == 50
    assert result.cpu["edge"] <= 20.0 + 1e-9
    # every topic a desktop monitor reads is received there: 10 ms each
    assert result.objective == pytest.approx(10.0 * len(result.received["desktop"]))


def test_threshold_caps_the_node():
    doc = _case_study_1()
    doc["nodes"][0]["threshold"] = 60  # 100 % available, 60 % threshold: 60 % usable
    doc["nodes"][0]["available_cpu"] = 70.0  # 30 % used by other tasks: 30 % left under the threshold
    stats = MonitorStats.from_dict(doc)
    assert stats.capacity()["edge"] == pytest.approx(30.0)
    result = allocate(stats)
    assert result.cpu["edge"] <= 30.0 + 1e-9
    assert sum(1 for v in result.allocation.values() if v == "edge") == 39  # 39 x 0.76 = 29.64


def test_unchanged_input_causes_no_migration():
    doc = _case_study_1(edge_available=20.0)
    first = allocate(doc)
    for m in doc["monitors"]:
        m["current"] = first.allocation[m["name"]]
    again = allocate(doc)
    assert again.migrations == [] and again.objective == pytest.approx(first.objective)


def test_literal_topic_coupling_receives_every_topic_where_any_monitor_runs():
    doc = _case_study_1(edge_available=10.0)
    result = allocate(doc, literal_topic_coupling=True)
    for node, topics in result.received.items():
        hosts = any(v == node for v in result.allocation.values())
        assert topics == (sorted(t["name"] for t in doc["topics"]) if hosts else [])


def _random_instance(rng, monitors, nodes, topics, tight):
    node_names = [f"n{j}" for j in range(nodes)]
    pub = {f"/t{k}": rng.choice(node_names) for k in range(topics)}
    return _doc(
        [{"name": j, "available_cpu": rng.uniform(*tight), "threshold": rng.choice([100, 90, 80])} for j in node_names],
        [
            {
                "name": k,
                "delay": {j: 0.0 if j == pub[k] else round(rng.uniform(1, 50), 1) for j in node_names},
                "cpu": {j: 0.0 if j == pub[k] else round(rng.uniform(0, 1), 2) for j in node_names},
            }
            for k in pub
        ],
        [
            {
                "name": f"m{i}",
                "topics": rng.sample(sorted(pub), rng.randint(1, min(2, topics))),
                "cpu": {j: round(rng.uniform(1, 8), 1) for j in node_names},
                "current": rng.choice(node_names),
                "tolerant": rng.random() < 0.5,
                "active_instances": rng.randint(0, 5),
            }
            for i in range(monitors)
        ],
    )


def _brute_force(stats):
    cpu = complete_cpu(stats)
    cap = stats.capacity()
    best_feasible, best_excess = None, None
    for combo in itertools.product(range(len(stats.nodes)), repeat=len(stats.monitors)):
        load = [0.0] * len(stats.nodes)
        received = [set() for _ in stats.nodes]
        for a, b in enumerate(combo):
            load[b] += cpu[a, b]
            received[b].update(stats.monitor_topics[stats.monitors[a]])
        delay = 0.0
        for b, topics in enumerate(received):
            for k in topics:
                load[b] += stats.topic_cpu[k].get(stats.nodes[b], 0.0)
                delay += stats.delay[k][stats.nodes[b]]
        excess = sum(max(0.0, load[b] - cap[j]) for b, j in enumerate(stats.nodes))
        if excess <= 1e-9:
            best_feasible = delay if best_feasible is None else min(best_feasible, delay)
        key = (round(excess, 6), delay)
        best_excess = key if best_excess is None else min(best_excess, key)
    return best_feasible, best_excess


def test_optimal_against_brute_force_on_small_instances():
    rng = random.Random(4)
    infeasible = 0
    for trial in range(60):
        doc = _random_instance(rng, monitors=rng.randint(1, 6), nodes=3, topics=3, tight=(5, 25))
        stats = MonitorStats.from_dict(doc)
        result = allocate(stats, epsilon=0.0)
        best_feasible, (min_excess, delay_at_min) = _brute_force(stats)
        if best_feasible is None:
            infeasible += 1
            assert not result.feasible and result.status == "overloaded", trial
            assert sum(result.overloaded.values()) == pytest.approx(min_excess, abs=1e-5)
            assert result.objective == pytest.approx(delay_at_min, abs=1e-6)
        else:
            assert result.feasible and result.status == "optimal", trial
            assert result.objective == pytest.approx(best_feasible, abs=1e-6), trial
            for j, share in result.cpu.items():  # capacity constraints hold
                assert share <= result.capacity[j] + 1e-6
    assert 5 < infeasible < 55


def _overload_doc(b_available, soft_tolerant=True):
    return _doc(
        [{"name": "a", "available_cpu": 10.0}, {"name": "b", "available_cpu": b_available}],
        [{"name": "/x", "delay": {"a": 0.0, "b": 5.0}, "cpu": {"a": 0.0, "b": 0.0}}],
        [
            {"name": "hard", "topics": ["/x"], "cpu": {"a": 6.0, "b": 6.0}, "current": "a", "active_instances": 3},
            {"name": "soft1", "topics": ["/x"], "cpu": {"a": 3.0, "b": 3.0}, "current": "a",
             "tolerant": soft_tolerant},
            {"name": "soft2", "topics": ["/x"], "cpu": {"a": 3.0, "b": 3.0}, "current": "a",
             "tolerant": soft_tolerant, "active_instances": 1},
        ],
    )  # fmt: skip


def test_overloaded_units_get_priorities_and_tolerant_monitors_drop():
    # 12 % of monitors, 10 % + 2 % of capacity, in pieces of 6, 3, 3: the least excess is 1 % on b
    result = allocate(_overload_doc(2.0))
    assert not result.feasible and result.status == "overloaded"
    assert result.overloaded == {"b": pytest.approx(1.0)}
    (on_b,) = [m for m, j in result.allocation.items() if j == "b"]
    assert on_b.startswith("soft")
    assert result.priorities == {on_b: 1 if on_b == "soft2" else 0}  # strategy 1: active instances
    assert result.drop_events == [on_b] and result.unresolved == {}  # strategy 2: tolerant, covers 1 %


def test_overload_without_tolerant_monitors_stays_unresolved():
    result = allocate(_overload_doc(2.0, soft_tolerant=False))
    assert result.drop_events == [] and result.unresolved == {"b": pytest.approx(1.0)}


def test_missing_cpu_statistic_is_scaled_by_node_speed():
    doc = _doc(
        [
            {"name": "edge", "available_cpu": 50.0, "speed": 1.0},
            {"name": "server", "available_cpu": 50.0, "speed": 2.0},
        ],
        [],
        [{"name": "m", "topics": [], "cpu": {"edge": 0.8}, "current": "edge"}],
    )
    cpu = complete_cpu(MonitorStats.from_dict(doc))
    assert cpu.tolist() == [[0.8, 0.4]]
    assert complete_cpu(MonitorStats.from_dict(doc), observed={("m", "server"): 0.3}).tolist() == [[0.8, 0.3]]


def test_sma_filter_averages_the_last_ten_statistics():
    f = StatsFilter(window=10)
    doc = _case_study_1()
    for t in range(15):
        doc["nodes"][0]["available_cpu"] = float(t)
        out = f.update(MonitorStats.from_dict(doc))
    assert out.available["edge"] == pytest.approx(sum(range(5, 15)) / 10)
    assert out.available["desktop"] == 100.0


def test_allocator_filters_spikes():
    allocator = MonitorAllocator(window=10)
    doc = _case_study_1()
    for _ in range(9):
        assert allocator.step(doc).migrations == []
    spike = _case_study_1(edge_available=5.0)  # one bad sample: the average is still 90.5 %
    assert allocator.step(spike).migrations == []


@pytest.mark.parametrize(
    ("mutate", "message"),
    [
        (lambda d: d.update(format="other"), "format must be"),
        (lambda d: d.update(nodes=[]), "'nodes' must be a non-empty list"),
        (lambda d: d["nodes"].append(dict(d["nodes"][0])), "node 'edge' is listed twice"),
        (lambda d: d["nodes"][0].update(available_cpu=120), "node 'edge': available_cpu: must be <= 100"),
        (lambda d: d["nodes"][0].update(available_cpu="lots"), "expected a number"),
        (lambda d: d["monitors"][0].update(topics=["/nope"]), "monitor 'm0': unknown topic '/nope'"),
        (lambda d: d["monitors"][0].update(current="mars"), "current node 'mars' is not a listed node"),
        (lambda d: d["monitors"][0].update(cpu={}), "monitor 'm0': no CPU statistic"),
        (lambda d: d["monitors"][0]["cpu"].update(moon=1), "unknown node 'moon'"),
        (lambda d: d["topics"][0]["delay"].pop("server"), "no delay for node 'server'"),
        (lambda d: d["monitors"].append(dict(d["monitors"][0])), "monitor 'm0' is listed twice"),
    ],
)
def test_bad_statistics_are_rejected_with_the_element_named(mutate, message):
    doc = _case_study_1(n=3)
    mutate(doc)
    with pytest.raises(InputError, match=message):
        allocate(doc)


def test_candidate_restriction_limits_the_units():
    # with one candidate (the current unit, which is also where the topics arrive first) nothing can move
    result = allocate(_case_study_1(edge_available=20.0), max_candidates=1)
    assert set(result.allocation.values()) == {"edge"} and not result.feasible
    assert allocate(_case_study_1(edge_available=20.0), max_candidates=2).feasible


def _robots_instance(rng, robots=2, per_robot=3):
    """Robots publish their own topics; monitors read one robot's topics and run there; one shared 'mid'
    unit with limited room: blocks per robot that must sometimes be merged."""
    names = [f"r{r}" for r in range(robots)] + ["mid"]
    topics, monitors = [], []
    for r in range(robots):
        for t in range(2):
            topics.append({
                "name": f"/r{r}/t{t}",
                "delay": {j: 0.0 if j == f"r{r}" else 10.0 + rng.randint(0, 5) if j == "mid" else 20.0 for j in names},
                "cpu": {j: 0.0 if j == f"r{r}" else round(rng.uniform(0, 1), 2) for j in names},
            })  # fmt: skip
        for i in range(per_robot):
            monitors.append({
                "name": f"m{r}_{i}",
                "topics": rng.sample([f"/r{r}/t0", f"/r{r}/t1"], rng.randint(1, 2)),
                "cpu": {j: round(rng.uniform(2, 6), 1) for j in names},
                "current": f"r{r}",
            })  # fmt: skip
    nodes = [{"name": f"r{r}", "available_cpu": rng.uniform(4, 14)} for r in range(robots)]
    nodes.append({"name": "mid", "available_cpu": rng.uniform(3, 16)})
    return _doc(nodes, topics, monitors)


@pytest.mark.parametrize("decompose", [True, False])
def test_block_decomposition_and_relief_covers_are_exact(decompose):
    # robot-structured instances exercise the per-robot blocks (and their merging when the shared unit
    # overflows) and the relief-cover rows of overloaded robots; brute force is the oracle
    rng = random.Random(11)
    split = merged = 0
    for trial in range(60):
        robots = rng.choice([2, 3])
        stats = MonitorStats.from_dict(_robots_instance(rng, robots=robots, per_robot=rng.choice([2, 3])))
        if len(stats.monitors) > 7:
            continue
        result = allocate(stats, epsilon=0.0, decompose=decompose)
        best_feasible, (min_excess, _) = _brute_force(stats)
        if best_feasible is None:
            assert not result.feasible and sum(result.overloaded.values()) == pytest.approx(min_excess, abs=1e-5)
            continue
        assert result.feasible and result.status == "optimal", trial
        assert result.objective == pytest.approx(best_feasible, abs=1e-6), trial
        assert all(result.cpu[j] <= result.capacity[j] + 1e-6 for j in result.cpu)
        split += result.blocks == robots
        merged += result.blocks < robots
    if decompose:
        assert split > 3 and merged > 2  # independent robots, and robots merged over the shared unit
