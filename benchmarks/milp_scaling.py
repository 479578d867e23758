"""Monitor-allocation MILP (Eqs. 3.21-3.22) solve time vs monitor and node counts.

    python benchmarks/milp_scaling.py [--time-limit S] [--work-limit NODES] [--quick]
        [--formulations covers,classes[,textbook]] [--sizes 500x5,1000x20] [--skip-case-studies] [--skip-growth]

Instances:
  * case study 1 (spec 03 §13.1/§14): 50 monitors, 5 topics published on edge, edge/desktop/server with
    10/100 ms delays, per-monitor CPU 0.76/0.5/0.36 %; the edge availability follows the testbench load
    (100 % down to 10 %); the thesis reports 27 ms per allocation period.
  * case study 2 (§13.2): 201 monitors on MCB/Jetson/server with thresholds 40/60/90 %.
  * fleets: n_nodes - n_nodes//5 - 1 robots (edge, threshold 60 %), n_nodes//5 intermediate units and one
    cloud; 4 topics per robot; each monitor reads 1-3 topics of one robot and, with probability
    ``cross``, also one topic of another robot. Delays: same unit 0.1 ms, edge-edge 20,
    edge-intermediate 10, cloud 100 (+ up to 1 ms noise). Robots are busy (edge available CPU drawn per
    robot), so part of the monitors must leave their robot. ``uniform`` gives every monitor the same CPU
    per unit kind (as in the thesis's case study 1), ``heterogeneous`` draws each monitor's CPU in
    [0.3, 1.2] % (per unit speed).
    - robot-local (cross = 0): every assertion is about one robot, as in the thesis's case studies. The
      MILP splits into one block per robot (allocate's decomposition), coupled only through the
      receiving units' capacities.
    - cross-robot (cross = 0.1): 10 % of the monitors also read another robot's topic, which ties every
      robot into one block; the LP relaxation then spreads every topic over the intermediate units in
      fractions (cross-robot reads cost it nothing), and large instances stop at the limit with a gap.
Every fleet is solved by each formulation of ``--formulations`` in turn, in the same run (the first is
the one measured, the others its references: "classes" is the previous model, "textbook" Eqs.
3.21-3.22 as written). Each line: wall and CPU time, status (optimal = within HiGHS's 0.01 % gap), the
remaining gap when the budget stopped it (100 % when not even the root bound was reached), total delay,
HiGHS's dual bound after the root node and at the end (model objective: delay - ε per monitor kept),
branch-and-bound nodes, migrations, independent blocks. The time limit is wall-clock, so on a loaded
machine the stopped runs get less CPU: read the CPU column, and compare formulations within one run.
"""

from __future__ import annotations

import argparse
import random
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from benchmarks._bench import loadavg
from continuum.engine.verification.monitor_milp import FORMULATIONS, MonitorStats, allocate


def case_study_1(edge_available: float) -> dict:
    nodes = [
        {"name": "edge", "available_cpu": edge_available},
        {"name": "desktop", "available_cpu": 100.0},
        {"name": "server", "available_cpu": 100.0},
    ]
    topics = [
        {
            "name": f"/t{k}",
            "delay": {"edge": 0.0, "desktop": 10.0, "server": 100.0},
            "cpu": {"edge": 0.0, "desktop": 0.2, "server": 0.2},
        }
        for k in range(5)
    ]
    monitors = [
        {
            "name": f"m{i}",
            "topics": [f"/t{i % 5}", f"/t{(i + 1) % 5}"],
            "cpu": {"edge": 0.76, "desktop": 0.5, "server": 0.36},
            "current": "edge",
        }
        for i in range(50)
    ]
    return {"format": "continuum.monitorstats/v1", "nodes": nodes, "topics": topics, "monitors": monitors}


def case_study_2(seed: int) -> dict:
    rng = random.Random(seed)
    nodes = [
        {"name": "mcb", "available_cpu": 100 - 23.44, "threshold": 40},
        {"name": "jetson", "available_cpu": 100 - 38.64, "threshold": 60},
        {"name": "server", "available_cpu": 100 - 30.96, "threshold": 90},
    ]
    pub = ["mcb", "jetson"]
    topics = []
    for k in range(20):
        src = pub[k % 2]
        topics.append(
            {
                "name": f"/t{k}",
                "delay": {
                    n["name"]: 0.1 if n["name"] == src else (1.0 if n["name"] != "server" else 8.0) for n in nodes
                },
                "cpu": {n["name"]: 0.0 if n["name"] == src else 0.1 for n in nodes},
            }
        )
    monitors = [
        {
            "name": f"m{i}",
            "topics": [f"/t{k}" for k in rng.sample(range(20), rng.randint(1, 3))],
            "cpu": {"mcb": 0.09, "jetson": 0.2, "server": 0.1},
            "current": "jetson",
        }
        for i in range(201)
    ]
    return {"format": "continuum.monitorstats/v1", "nodes": nodes, "topics": topics, "monitors": monitors}


def fleet(n_monitors: int, n_nodes: int, seed: int, uniform: bool, cross: float = 0.1) -> dict:
    rng = random.Random(seed)
    n_mid = max(1, n_nodes // 5)
    n_edge = n_nodes - n_mid - 1
    kinds = ["edge"] * n_edge + ["mid"] * n_mid + ["cloud"]
    speed = {"edge": 1.0, "mid": 2.0, "cloud": 4.0}
    threshold = {"edge": 60, "mid": 80, "cloud": 90}
    names = [f"{k}{j}" for j, k in enumerate(kinds)]
    nodes = [
        {
            "name": names[j],
            "available_cpu": round(100 - (rng.uniform(10, 45) if k == "edge" else rng.uniform(10, 40)), 1),
            "threshold": threshold[k],
            "speed": speed[k],
        }
        for j, k in enumerate(kinds)
    ]

    def latency(a: int, b: int) -> float:
        if a == b:
            return 0.1
        if "cloud" in (kinds[a], kinds[b]):
            return 100.0
        return 20.0 if kinds[a] == kinds[b] == "edge" else 10.0

    topics, by_robot = [], {}
    for r in range(n_edge):
        for t in range(4):
            name = f"/r{r}/t{t}"
            by_robot.setdefault(r, []).append(name)
            topics.append(
                {
                    "name": name,
                    "delay": {names[j]: round(latency(r, j) + rng.uniform(0, 1), 2) for j in range(n_nodes)},
                    "cpu": {names[j]: 0.0 if j == r else round(0.2 / speed[kinds[j]], 3) for j in range(n_nodes)},
                }
            )
    monitors = []
    for i in range(n_monitors):
        r = rng.randrange(n_edge)
        reads = rng.sample(by_robot[r], rng.randint(1, 3))
        if n_edge > 1 and rng.random() < cross:
            reads.append(rng.choice(by_robot[rng.choice([o for o in range(n_edge) if o != r])]))
        base = 0.76 if uniform else rng.uniform(0.3, 1.2)
        monitors.append(
            {
                "name": f"m{i}",
                "topics": reads,
                "cpu": {names[j]: round(base / speed[kinds[j]], 3) for j in range(n_nodes)},
                "current": names[r],
            }
        )
    return {"format": "continuum.monitorstats/v1", "nodes": nodes, "topics": topics, "monitors": monitors}


def solve(doc: dict, **options) -> tuple[float, float, object]:
    """(wall ms, CPU ms of this process, Allocation). HiGHS runs single-threaded in this process, so the
    CPU time is what the solve cost whatever else the shared machine is doing."""
    stats = MonitorStats.from_dict(doc)
    t0, c0 = time.perf_counter(), time.process_time()
    result = allocate(stats, **options)
    return (time.perf_counter() - t0) * 1000, (time.process_time() - c0) * 1000, result


def line(label: str, ms: float, r, cpu_ms: float | None = None) -> str:
    state = r.status if r.feasible or r.status != "overloaded" else "overloaded"
    gap = f"gap {r.gap:.2%}" if r.status == "time_limit" else ""
    cpu = f" cpu {cpu_ms:8.1f} ms" if cpu_ms is not None else ""
    bounds = f"  root {_num(r.root_bound)} bound {_num(r.bound)} nodes {r.nodes:5d}" if cpu_ms is not None else ""
    return (
        f"{label:<44} {ms:9.1f} ms{cpu}  {state:<10} {gap:<11} delay {r.objective:9.2f}{bounds}"
        f"  {len(r.migrations):4d} migr.  {r.blocks:3d} block(s)"
    )


def _num(v: float) -> str:
    return f"{v:9.2f}" if v > -1e300 else "      n/a"


FLEETS = [
    ("robot-local uniform", True, 0.0),
    ("robot-local heterogeneous", False, 0.0),
    ("cross-robot uniform", True, 0.1),
    ("cross-robot heterogeneous", False, 0.1),
]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--time-limit", type=float, default=5.0, help="seconds per allocate() call")
    parser.add_argument(
        "--work-limit", type=int, default=None, help="branch-and-bound nodes per solve (reproducible budget)"
    )
    parser.add_argument("--quick", action="store_true", help="fewer and smaller fleets")
    parser.add_argument(
        "--formulations",
        default="covers,classes",
        help="comma-separated, first = the one measured, the others its references, side by side "
        f"(choices: {', '.join(FORMULATIONS)}; textbook = Eqs. 3.21-3.22 as written)",
    )
    parser.add_argument("--sizes", default=None, help="monitors x nodes list, e.g. 500x5,1000x20")
    parser.add_argument("--skip-case-studies", action="store_true")
    parser.add_argument("--skip-growth", action="store_true")
    args = parser.parse_args()
    forms = [f.strip() for f in args.formulations.split(",") if f.strip()]
    bad = [f for f in forms if f not in FORMULATIONS]
    if bad or not forms:
        print(f"milp_scaling: unknown formulation {bad[0] if bad else ''!r}", file=sys.stderr)
        sys.exit(2)
    try:
        sizes = (
            [tuple(int(v) for v in s.lower().split("x")) for s in args.sizes.split(",")]
            if args.sizes
            else ([(100, 5), (250, 10)] if args.quick else [(500, 5), (500, 10), (500, 20), (1000, 20)])
        )
        if any(len(s) != 2 or s[0] < 1 or s[1] < 3 for s in sizes):
            raise ValueError
    except ValueError:
        print("milp_scaling: --sizes must look like 500x5,1000x20 (at least 3 nodes)", file=sys.stderr)
        sys.exit(2)
    budget = {"time_limit": args.time_limit}
    if args.work_limit is not None:
        budget["work_limit"] = args.work_limit
    print(f"load average at start: {loadavg()}; budget {budget}; formulations {forms}")

    if not args.skip_case_studies:
        profile = [100, 100, 60, 40, 30, 25, 20, 15, 10, 10, 20, 40, 80, 100]
        for form in forms:
            times, cpus, statuses = [], [], []
            for avail in profile:
                ms, cpu_ms, r = solve(case_study_1(avail), formulation=form, **budget)
                times.append(ms)
                cpus.append(cpu_ms)
                statuses.append(r.status)
            print(
                f"case study 1 (50 x 3 x 5) [{form}], {len(profile)} periods: mean {statistics.mean(times):.1f} ms "
                f"(cpu {statistics.mean(cpus):.1f}), max {max(times):.1f} ms, statuses {sorted(set(statuses))}"
                "  (thesis: 27 ms per period)"
            )
            ms, cpu_ms, r = solve(case_study_2(0), formulation=form, **budget)
            print(line(f"case study 2 (201 x 3 x 20) [{form}]", ms, r, cpu_ms))

    print("\nsolve time, side by side (same instances, same run)")
    table: dict[str, dict[tuple[int, int], str]] = {}
    for label, uniform, cross in FLEETS:
        for n_mon, n_nodes in sizes:
            doc = fleet(n_mon, n_nodes, seed=n_mon + n_nodes, uniform=uniform, cross=cross)
            cpu_of = {}
            for form in forms:
                ms, cpu_ms, r = solve(doc, formulation=form, **budget)
                cpu_of[form] = cpu_ms
                print(line(f"{label} {n_mon} x {n_nodes} [{form}]", ms, r, cpu_ms))
                mark = "" if r.status == "optimal" else f"*{r.gap:.0%}"
                table.setdefault(f"{label} [{form}]", {})[(n_mon, n_nodes)] = f"{cpu_ms / 1000:.2f}{mark}"
            for ref in forms[1:]:
                print(f"{'':<44} cpu ratio {forms[0]}/{ref}: {cpu_of[forms[0]] / max(cpu_of[ref], 1e-9):.2f}")
    print("\nCPU seconds to optimality (*g = stopped by the budget with gap g, not proven optimal)")
    print(f"{'':<40}" + "".join(f"{f'{m} x {n}':>12}" for m, n in sizes))
    for label, row in table.items():
        print(f"{label:<40}" + "".join(f"{row[s]:>12}" for s in sizes))

    if not args.skip_growth:
        print("\ngrowth with monitors (20 nodes), CPU seconds")
        counts = [100, 250, 500, 1000] if not args.quick else [100, 250]
        for label, uniform, cross in FLEETS:
            for form in forms:
                cells = []
                for n_mon in counts:
                    doc = fleet(n_mon, 20, seed=n_mon + 20, uniform=uniform, cross=cross)
                    _, cpu_ms, r = solve(doc, formulation=form, **budget)
                    cells.append(f"{cpu_ms / 1000:.2f}" + ("" if r.status == "optimal" else f"*{r.gap:.0%}"))
                print(f"{label + ' [' + form + ']':<40}" + "".join(f"{c:>12}" for c in cells) + f"   ({counts})")
    print(f"load average at end: {loadavg()}")


if __name__ == "__main__":
    main()
