"""How ``tests/data/fig-3.29.dag.json`` was found (a thesis scenario: searched for the thesis' four makespans).

The thesis gives, for one DAG on two nodes with two CPUs each, the makespans 14.7 ms (default Kubernetes),
11 ms (ideal HEFT), 13.3 ms (HEFT on Kubernetes) and, via the speedups, 11.0 ms for HEFT4K, with the critical
path A -> F -> G. This script searches (seeded simulated annealing over integer costs 1..9 per node, edges
and data sizes 0..4 Mbit, links of 750 Mbit/s, the Table 4.28 mean) for a DAG whose HEFT plan and simulated
executions give exactly those figures (rounded to 0.1 ms as printed), with the default-Kubernetes model's
random tie-break seed among 0..7. Run: ``python benchmarks/fig329_search.py [seed] [tasks]``
(``python benchmarks/fig329_search.py 1 ABCDEFGH`` reproduces the fixture in a few minutes).
"""

from __future__ import annotations

import json
import math
import random
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from continuum.engine import Platform, TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.heft4k.heft4k import heft4k
from continuum.engine.heft4k.k8s_baselines import run_heft4k, run_heft_k8s, run_k8s_default

TARGET = {"ideal": 11.0, "heft4k": 11.0, "heft-k8s": 13.333, "k8s": 14.667}
SEEDS = range(8)
PLATFORM = Platform.from_dict({"processors": [{"id": "N1", "cores": 2}, {"id": "N2", "cores": 2}], "bandwidth": 0.75})


def build(state: dict, names: list[str]) -> TaskGraph:
    tasks = [{"id": t, "cost": {"N1": state["c"][t][0], "N2": state["c"][t][1]}} for t in names]
    edges = [{"src": s, "dst": d, "data": state["e"][(s, d)]} for (s, d) in sorted(state["e"])]
    return TaskGraph.from_dict({"name": "fig-3.29", "tasks": tasks, "edges": edges})


def score(state: dict, names: list[str]) -> tuple[float, tuple | None]:
    try:
        dag = build(state, names)
    except InputError:  # a mutation made a cycle
        return 1e9, None
    plan = heft4k(dag, PLATFORM)
    path = [t for t, _ in plan.critical_path(dag, PLATFORM)]
    ideal = plan.makespan
    nice = run_heft4k(dag, PLATFORM, plan).makespan
    plain = run_heft_k8s(dag, PLATFORM, plan).makespan
    k8s = [run_k8s_default(dag, PLATFORM, seed=s).makespan for s in SEEDS]
    best = min(k8s, key=lambda k: abs(k - TARGET["k8s"]))
    penalty = 0 if path == ["A", "F", "G"] else 2
    value = (
        3 * abs(ideal - TARGET["ideal"])
        + 3 * abs(nice - TARGET["heft4k"])
        + abs(plain - TARGET["heft-k8s"])
        + abs(best - TARGET["k8s"])
        + penalty
    )
    ok = (
        abs(ideal - 11) < 1e-9
        and round(nice, 1) == 11.0
        and round(plain, 1) == 13.3
        and round(best, 1) == 14.7
        and not penalty
    )
    return value, (ok, ideal, nice, plain, best, k8s.index(best), path)


def mutate(state: dict, rng: random.Random, names: list[str]) -> dict:
    state = {"c": {k: list(v) for k, v in state["c"].items()}, "e": dict(state["e"])}
    r = rng.random()
    if r < 0.5:
        t, i = rng.choice(names), rng.randint(0, 1)
        state["c"][t][i] = max(1, min(9, state["c"][t][i] + rng.choice([-1, 1])))
    elif r < 0.75 and state["e"]:
        k = rng.choice(sorted(state["e"]))
        state["e"][k] = max(0, min(4, state["e"][k] + rng.choice([-1, 1])))
    else:
        s, d = sorted(rng.sample(names, 2), key=names.index)
        if (s, d) in state["e"] and (s, d) not in {("A", "F"), ("F", "G")}:
            del state["e"][(s, d)]
        elif s != "G" and d != "A":
            state["e"][(s, d)] = rng.randint(0, 3)
    return state


def main(seed: int = 1, names: str = "ABCDEFGH", restarts: int = 30, steps: int = 3000) -> None:
    rng = random.Random(seed)
    tasks = list(names)
    mids = [x for x in tasks if x not in "AFG"]
    for restart in range(restarts):
        state = {"c": {t: [rng.randint(1, 6), rng.randint(1, 6)] for t in tasks}, "e": {("A", "F"): 1, ("F", "G"): 1}}
        for t in mids:
            state["e"][("A", t)] = rng.randint(0, 2)
            state["e"][(t, "G")] = rng.randint(0, 2)
        cur, info = score(state, tasks)
        temperature = 1.0
        for step in range(steps):
            new = mutate(state, rng, tasks)
            value, new_info = score(new, tasks)
            if value < cur or rng.random() < math.exp((cur - value) / max(temperature, 1e-3)):
                state, cur, info = new, value, new_info
                if info and info[0]:
                    print(f"found at restart {restart} step {step}: {info}")
                    print(json.dumps(build(state, tasks).to_dict()))
                    return
            temperature *= 0.999
        print(f"restart {restart}: best score {cur:.3f} {info}", flush=True)
    print("not found")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1, sys.argv[2] if len(sys.argv) > 2 else "ABCDEFGH")
