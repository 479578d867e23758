"""The CFS simulator: nice weights, fluid sharing, pub/sub precedence, transfers, and invariants."""

import itertools
import random

import pytest

from continuum.engine import InputError, Platform, TaskGraph
from continuum.engine.heft4k.cfs_sim import NICE_WEIGHTS, cpu_rates, nice_weight, simulate
from continuum.engine.heft4k.heft4k import heft4k

from .test_heft4k import random_cluster, random_dag


def two_tasks(cores=1):
    dag = TaskGraph.from_dict({"tasks": [{"id": x, "cost": {"cpu": 4}} for x in "ab"], "edges": []})
    return dag, Platform.from_dict({"processors": [{"id": "n", "cores": cores}]})


def finish(schedule):
    return {a.task: a.finish for a in schedule.assignments}


def test_kernel_weight_table():
    assert len(NICE_WEIGHTS) == 40
    assert (nice_weight(-20), nice_weight(0), nice_weight(19)) == (88761, 1024, 15)
    assert nice_weight(5) == 335 and nice_weight(-5) == 3121
    assert nice_weight(40) == 15  # clamped like setpriority


def test_equal_niceness_shares_one_cpu_fairly():
    dag, platform = two_tasks()
    s = simulate(dag, platform, {"a": "n", "b": "n"})
    assert finish(s) == {"a": 8.0, "b": 8.0}
    assert s.metrics["busy"] == {"n": 8.0}


def test_nice_19_leaves_almost_all_the_cpu_to_nice_0():
    dag, platform = two_tasks()
    s = simulate(dag, platform, {"a": "n", "b": "n"}, {"b": 19})
    assert finish(s)["a"] == pytest.approx(4 * (1024 + 15) / 1024)  # 4.0586 ms
    assert finish(s)["b"] == pytest.approx(8.0)


def test_two_cpus_run_two_tasks_without_interference():
    dag, platform = two_tasks(cores=2)
    s = simulate(dag, platform, {"a": "n", "b": "n"}, {"b": 19})
    assert finish(s) == {"a": 4.0, "b": 4.0}


def test_water_filling_caps_a_task_at_one_cpu():
    assert cpu_rates([1024, 15, 15], 2) == [1.0, 0.5, 0.5]
    assert cpu_rates([1024, 1024, 1024], 2) == pytest.approx([2 / 3] * 3)
    assert cpu_rates([1024, 1024], 4) == [1.0, 1.0]
    rates = cpu_rates([3121, 1024, 335, 15], 2)
    assert sum(rates) == pytest.approx(2.0) and rates[0] == 1.0
    assert rates[1] / rates[2] == pytest.approx(1024 / 335)


def test_a_late_arrival_preempts_and_counts():
    # b arrives at 2 (its input from a on the other node takes 1 ms) and halves c's CPU share.
    dag = TaskGraph.from_dict(
        {
            "tasks": [
                {"id": "a", "cost": {"cpu": 1}},
                {"id": "b", "cost": {"cpu": 2}},
                {"id": "c", "cost": {"cpu": 4}},
            ],
            "edges": [{"src": "a", "dst": "b", "data": 1.0}],
        }
    )
    platform = Platform.from_dict({"processors": [{"id": "n1"}, {"id": "n2"}], "bandwidth": 1.0})
    s = simulate(dag, platform, {"a": "n1", "b": "n2", "c": "n2"}, ranks={"a": 3, "b": 2, "c": 1})
    starts = {a.task: a.start for a in s.assignments}
    assert starts == {"a": 0.0, "c": 0.0, "b": 2.0}
    # c runs alone 2 ms, then b and c share: b needs 4 ms at half speed, c's last 2 ms too.
    assert finish(s) == {"a": 1.0, "b": 6.0, "c": 6.0}
    assert s.metrics["preemptions"] == 1
    assert s.metrics["transfers"] == [{"src": "a", "dst": "b", "from": "n1", "to": "n2", "start": 1.0, "finish": 2.0}]
    assert s.metrics["traffic_mbit"] == 1.0
    # b (rank 2) is slowed while c (rank 1) runs from 2 to 6, and c gets half a CPU meanwhile.
    assert s.metrics["priority_inversion_time"] == pytest.approx(4.0)
    assert s.metrics["priority_inversion_cpu"] == pytest.approx(2.0)
    assert s.metrics["segments"]["c"] == [[0.0, 2.0, 1.0], [2.0, 6.0, 0.5]]


def test_bad_placements_are_rejected():
    dag, platform = two_tasks()
    with pytest.raises(InputError, match="task 'b' is not placed"):
        simulate(dag, platform, {"a": "n"})
    with pytest.raises(InputError, match="unknown node 'x'"):
        simulate(dag, platform, {"a": "n", "b": "x"})
    gpu = TaskGraph.from_dict({"tasks": [{"id": "g", "cost": {"gpu": 1}}], "edges": []})
    with pytest.raises(InputError, match="task 'g' cannot run on node 'n'"):
        simulate(gpu, platform, {"g": "n"})


@pytest.mark.parametrize("seed", range(12))
def test_invariants_on_generated_dags(seed):
    rng = random.Random(seed)
    nodes = [f"n{i}" for i in range(rng.randint(2, 5))]
    dag = random_dag(rng, rng.randint(3, 60), nodes)
    platform = random_cluster(rng, nodes)
    plan = heft4k(dag, platform)
    placement = {a.task: a.processor for a in plan.assignments}
    nice = {t: rng.randint(-20, 19) for t in dag.tasks}
    s = simulate(dag, platform, placement, nice, ranks=plan.ranks)
    got = {a.task: a for a in s.assignments}
    assert set(got) == set(dag.tasks)
    procs = {p.id: p for p in platform.processors}
    cost = {t: platform.cost(dag.tasks[t], procs[placement[t]]) for t in dag.tasks}
    # Precedence through publish/subscribe: a task starts once every input has arrived.
    for e in dag.edges:
        src, dst = got[e.src], got[e.dst]
        comm = platform.comm_time(src.processor, dst.processor, e.data) if src.processor != dst.processor else 0.0
        assert dst.start >= src.finish + comm - 1e-9
    # Entry tasks start at deployment; nobody runs faster than one CPU.
    for t, a in got.items():
        assert a.finish - a.start >= cost[t] - 1e-9
        if not any(e.dst == t for e in dag.edges):
            assert a.start == 0.0
    # Work conservation: every task gets exactly its cost of CPU time, and a node's busy time is their sum.
    seg = s.metrics["segments"]
    for t in dag.tasks:
        assert sum((b - a) * r for a, b, r in seg[t]) == pytest.approx(cost[t], rel=1e-6, abs=1e-6)
        assert seg[t][0][0] == got[t].start and seg[t][-1][1] == got[t].finish
    for n in nodes:
        assert s.metrics["busy"][n] == pytest.approx(sum(cost[t] for t in dag.tasks if placement[t] == n), abs=1e-6)
    # A node never uses more CPUs than it has, and never idles a CPU while a runnable task waits.
    for n in nodes:
        cuts = sorted({x for t in dag.tasks if placement[t] == n for a, b, _ in seg[t] for x in (a, b)})
        for lo, hi in itertools.pairwise(cuts):
            mid = (lo + hi) / 2
            live = [r for t in dag.tasks if placement[t] == n for a, b, r in seg[t] if a <= mid < b]
            assert sum(live) <= procs[n].cores + 1e-9
            assert sum(live) == pytest.approx(min(procs[n].cores, len(live)))
