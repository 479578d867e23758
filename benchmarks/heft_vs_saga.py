"""Continuum's HEFT against saga's (``anrg-saga==2.0.2``), side by side on the same DAGs.

Run on demand: ``python benchmarks/heft_vs_saga.py [--quick]``. saga is installed by this script into a
throw-away virtual environment under /tmp and run in a subprocess (it is never imported here).

Inputs: random layered DAGs of the HEFT literature (``continuum.engine.device.generators.layered_dag``: shape 1,
mean out-degree 3, CCR 1) with one zero-cost entry and exit task added (saga adds them itself otherwise),
on *related* machines - the cost model saga can express: a task of cost w takes w / speed on a processor
(speeds uniform in [0.5, 1.5]) and an edge of size d takes d / bandwidth between two processors (bandwidth
1 on every link, 0 on the same processor).

Measured: the wall time of the scheduling call only (ours: ``heft(dag, platform)`` including its
compilation of the DAG; saga: ``HeftScheduler().schedule(network, task_graph)`` with saga's rank cache
cleared), best of a few runs, and both makespans. The two HEFTs differ in one documented way: saga's mean
communication cost averages over the network's links *including* each node's link to itself (speed inf),
so its c_bar is (P-1)/(P+1) of ours (the literature's mean over distinct pairs); ranks, hence some
priority orders and makespans, differ slightly. To show that this is the only difference, the last
column runs our phase 2 (``schedule_list``) on saga's ranks and order and compares with saga.
Then: a 10,000-task DAG on 16 processors (time and peak memory of ours) and the growth exponents of
both in tasks (8 processors) and processors (1000 tasks).
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys
import tempfile
import tracemalloc
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _bench import best_of, ensure_venv, fit_exponent, table

from continuum.engine import TaskGraph
from continuum.engine.device.generators import layered_dag, related_platform
from continuum.engine.device.heft import compile_problem, heft, schedule_list

SAGA_VENV = Path(tempfile.gettempdir()) / "continuum-bench-saga-2.0.2"

SAGA_RUNNER = r"""
import json, sys, time
from saga import Network, TaskGraph
from saga.schedulers.cpop import upward_rank
from saga.schedulers.heft import HeftScheduler

out = []
for case in json.load(open(sys.argv[1])):
    tg = TaskGraph.create([tuple(t) for t in case["tasks"]], [tuple(e) for e in case["edges"]])
    nodes = [tuple(n) for n in case["nodes"]]
    names = [n[0] for n in nodes]
    links = [(a, b, case["bandwidth"]) for i, a in enumerate(names) for b in names[i + 1:]]
    net = Network.create(nodes, links)
    best, makespan = float("inf"), None
    for _ in range(case["repeats"]):
        upward_rank.cache_clear()
        start = time.perf_counter()
        schedule = HeftScheduler().schedule(net, tg)
        best = min(best, time.perf_counter() - start)
        makespan = schedule.makespan
    out.append({"seconds": best, "makespan": makespan, "tasks": len(tg.tasks)})
print(json.dumps(out))
"""


def instance(n: int, processors: int, seed: int):
    """A layered DAG with a single entry and exit, and a related-machine platform."""
    dag = layered_dag(n, seed=seed, shape=1.0, out_degree=3.0, ccr=1.0)
    doc = dag.to_dict()
    pred = {t: 0 for t in dag.tasks}
    succ = {t: 0 for t in dag.tasks}
    for e in dag.edges:
        pred[e.dst] += 1
        succ[e.src] += 1
    doc["tasks"] += [{"id": "entry", "cost": {"cpu": 0.0}}, {"id": "exit", "cost": {"cpu": 0.0}}]
    doc["edges"] += [{"src": "entry", "dst": t, "data": 0.0} for t, k in pred.items() if k == 0]
    doc["edges"] += [{"src": t, "dst": "exit", "data": 0.0} for t, k in succ.items() if k == 0]
    dag = TaskGraph.from_dict(doc)
    platform = related_platform(processors, seed=seed, heterogeneity=1.0, bandwidth=1.0)
    return dag, platform


def makespan_with_saga_ranks(dag: TaskGraph, platform) -> float:
    """Our list scheduler on saga's priority order: its ranks (c_bar over links incl. self-links) and sort."""
    prob = compile_problem(dag, platform)
    P = len(prob.names)
    c_unit = sum(prob.inv[i][j] for i in range(P) for j in range(i + 1, P)) / (P * (P + 1) / 2)
    indeg = [len(p) for p in prob.pred]
    topo = [t for t in range(prob.n) if indeg[t] == 0]
    for t in topo:
        for q, _ in prob.succ[t]:
            indeg[q] -= 1
            if indeg[q] == 0:
                topo.append(q)
    ranks = [0.0] * prob.n
    for t in reversed(topo):
        w = sum(c for _, c in prob.costs[t]) / len(prob.costs[t])
        ranks[t] = w + max((ranks[q] + d * c_unit for q, d in prob.succ[t]), default=0.0)
    back = {t: i for i, t in enumerate(reversed(topo))}
    order = sorted(range(prob.n), key=lambda t: (ranks[t], back[t]), reverse=True)
    placed = schedule_list(prob, order)
    return max(placed.finish)


def saga_case(dag: TaskGraph, platform, repeats: int) -> dict:
    return {
        "tasks": [[t.id, t.cost["cpu"]] for t in dag.tasks.values()],
        "edges": [[e.src, e.dst, e.data] for e in dag.edges],
        "nodes": [[p.id, p.speed] for p in platform.processors],
        "bandwidth": platform.bandwidth,
        "repeats": repeats,
    }


def run_saga(python: Path, cases: list[dict]) -> list[dict]:
    with tempfile.TemporaryDirectory() as tmp:
        spec, runner = Path(tmp) / "cases.json", Path(tmp) / "run_saga.py"
        spec.write_text(json.dumps(cases))
        runner.write_text(SAGA_RUNNER)
        done = subprocess.run([python, runner, spec], capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer sizes and seeds")
    parser.add_argument("--seeds", type=int, default=None, help="DAGs per configuration (default 3, quick 1)")
    args = parser.parse_args()
    seeds = range(args.seeds or (1 if args.quick else 3))
    by_tasks = [100, 500, 1000, 5000] if args.quick else [100, 250, 500, 1000, 2000, 5000]
    by_procs = [4, 8, 64] if args.quick else [4, 8, 16, 32, 64]
    configs = sorted({(n, 8) for n in by_tasks} | {(1000, p) for p in by_procs})

    python = ensure_venv(SAGA_VENV, "anrg-saga==2.0.2", "saga")
    rows, ours, cases = [], [], []
    for n, p in configs:
        repeats = 3 if n <= 1000 else 1
        for seed in seeds:
            dag, platform = instance(n, p, seed)
            schedule, seconds = best_of(lambda d=dag, pl=platform: heft(d, pl), repeats)
            assert schedule.violations(dag, platform) == []
            ours.append((n, p, seed, seconds, schedule.makespan, makespan_with_saga_ranks(dag, platform)))
            cases.append(saga_case(dag, platform, repeats))
    print(f"running saga on {len(cases)} DAGs ...", flush=True)
    theirs = run_saga(python, cases)

    per_config: dict[tuple[int, int], list] = {}
    for (n, p, _seed, sec, mk, mk_saga_ranks), saga in zip(ours, theirs, strict=True):
        per_config.setdefault((n, p), []).append((sec, saga["seconds"], mk, saga["makespan"], mk_saga_ranks))
    for (n, p), runs in sorted(per_config.items()):
        our_t = statistics.median(r[0] for r in runs)
        saga_t = statistics.median(r[1] for r in runs)
        diffs = [100 * (r[2] - r[3]) / r[3] for r in runs]
        same_rank = max(abs(100 * (r[4] - r[3]) / r[3]) for r in runs)
        rows.append(
            [n, p, 1000 * our_t, 1000 * saga_t, saga_t / our_t, statistics.mean(diffs), max(diffs, key=abs), same_rank]
        )
    print("\nHEFT, related machines, CCR 1 (median over seeds of the best-of-N wall time)")
    headers = ["tasks", "procs", "ours ms", "saga ms", "speedup x", "mean mk diff %", "worst mk diff %"]
    print(table([*headers, "|diff| % on saga ranks"], rows))
    all_diffs = [100 * (o[4] - t["makespan"]) / t["makespan"] for o, t in zip(ours, theirs, strict=True)]
    print(
        f"\nmakespan ours vs saga over {len(all_diffs)} DAGs: mean {statistics.mean(all_diffs):+.3f} %, "
        f"median {statistics.median(all_diffs):+.3f} %, |diff| <= 1 % on "
        f"{sum(abs(d) <= 1 for d in all_diffs)}/{len(all_diffs)}"
    )
    target = [r for r in rows if r[0] == 1000 and r[1] == 8]
    if target:
        print(f"goal 1000 tasks x 8 processors: {target[0][4]:.1f}x faster than saga (goal >= 10x)")

    tasks_rows = [r for r in rows if r[1] == 8]
    procs_rows = [r for r in rows if r[0] == 1000]
    print(
        "growth exponent in tasks (8 procs):  ours "
        f"{fit_exponent([r[0] for r in tasks_rows], [r[2] for r in tasks_rows]):.2f}, saga "
        f"{fit_exponent([r[0] for r in tasks_rows], [r[3] for r in tasks_rows]):.2f}"
    )
    print(
        "growth exponent in processors (1000 tasks): ours "
        f"{fit_exponent([r[1] for r in procs_rows], [r[2] for r in procs_rows]):.2f}, saga "
        f"{fit_exponent([r[1] for r in procs_rows], [r[3] for r in procs_rows]):.2f}"
    )

    dag, platform = instance(10_000, 16, 0)
    schedule, seconds = best_of(lambda: heft(dag, platform), 1)
    tracemalloc.start()
    heft(dag, platform)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(
        f"\n10,000 tasks ({len(dag.edges)} edges) on 16 processors: {seconds:.3f} s, makespan "
        f"{schedule.makespan:.1f}, peak traced memory of the call {peak / 2**20:.1f} MiB, "
        f"process max RSS {rss:.0f} MiB"
    )


if __name__ == "__main__":
    main()
