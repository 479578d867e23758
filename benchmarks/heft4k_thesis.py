"""HEFT4K against the thesis' figures (3.3.2 Figs. 3.29-3.31, 4.3.2 Table 4.28, Figs. 4.16-4.19), seeded.

Run: ``python benchmarks/heft4k_thesis.py [--dags N] [--seed S] [--json FILE]`` (default 150 DAGs, a few
minutes on one core). Everything runs in the CFS simulator of :mod:`continuum.engine.heft4k.cfs_sim`; the thesis
ran 100k DAGs on its own simulator, so compare orderings and magnitudes, not digits. Speedups follow spec
02 section 0: ``(M_baseline / M_heft4k - 1) * 100``; a node loss is a negative speedup.

1. the Fig. 3.29/3.30 example (reconstructed DAG in tests/data);
2. a Table 4.28-like corpus (:mod:`continuum.engine.heft4k.synthetic`), each DAG on its own random 6 x 2-CPU cluster,
   with default Kubernetes, HEFT on Kubernetes, HEFT4K, ideal HEFT and DPE (Figs. 4.16-4.18);
3. the remap experiment of Fig. 4.19: five successive random node losses, Algorithm 2 with theta = 20%;
4. the threshold calibration of Fig. 3.31 (delta = 10%).
"""

from __future__ import annotations

import argparse
import json
import random
import statistics
import sys
import time
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from continuum.engine import TaskGraph  # noqa: E402
from continuum.engine.core.cluster import cluster_platform  # noqa: E402
from continuum.engine.heft4k.heft4k import heft4k  # noqa: E402
from continuum.engine.heft4k.k8s_baselines import compare, run_heft4k, run_heft_k8s, run_k8s_default, speedup  # noqa: E402
from continuum.engine.heft4k.remap import calibrate_threshold, calibration_points, remap  # noqa: E402
from continuum.engine.heft4k.synthetic import TABLE_4_28, corpus_stats, dag_stats, random_cluster, random_dag  # noqa: E402

DATA = ROOT / "tests" / "data"


def q(values: list[float]) -> dict[str, float]:
    """n, mean, quartiles."""
    if not values:
        return {"n": 0}
    s = sorted(values)
    quart = statistics.quantiles(s, n=4) if len(s) > 1 else [s[0]] * 3
    return {"n": len(s), "mean": statistics.fmean(s), "q1": quart[0], "median": quart[1], "q3": quart[2]}


def fmt(stats: dict[str, float]) -> str:
    if not stats.get("n"):
        return "n=0"
    return (
        f"n={stats['n']:4d} mean {stats['mean']:7.1f}%  q1 {stats['q1']:7.1f}%  median {stats['median']:7.1f}%  "
        f"q3 {stats['q3']:7.1f}%"
    )


def size_bin(n: int, width: int = 32) -> str:
    lo = (n - 1) // width * width + 1
    return f"{lo:3d}-{lo + width - 1:3d}"


# ---- 1. Figs. 3.29 / 3.30 -------------------------------------------------------------------------
def example() -> dict:
    dag = TaskGraph.from_dict(json.loads((DATA / "fig-3.29.dag.json").read_text()))
    platform = cluster_platform(json.loads((DATA / "fig-3.29.cluster.json").read_text()))
    plan = heft4k(dag, platform)
    out = {
        "k8s-default": run_k8s_default(dag, platform, seed=1).makespan,
        "heft-ideal": plan.makespan,
        "heft-k8s": run_heft_k8s(dag, platform, plan).makespan,
        "heft4k": run_heft4k(dag, platform, plan).makespan,
    }
    thesis = {"k8s-default": 14.7, "heft-ideal": 11.0, "heft-k8s": 13.3, "heft4k": 11.0}
    print("== Figs. 3.29/3.30 (reconstructed DAG; 2 nodes x 2 CPUs) ==")
    for k, v in out.items():
        print(f"  {k:12} ours {v:6.2f} ms   thesis {thesis[k]:5.1f} ms")
    print(
        f"  HEFT4K vs HEFT on K8s {speedup(out['heft-k8s'], out['heft4k']):+.1f}% (thesis +20.9%), "
        f"vs K8s {speedup(out['k8s-default'], out['heft4k']):+.1f}% (thesis +33.6%)"
    )
    return out


# ---- 2. scheduler comparison -----------------------------------------------------------------------
def comparison(cases: list[tuple[TaskGraph, object]], seed: int) -> tuple[dict, list[dict]]:
    rows = []
    for i, (dag, platform) in enumerate(cases):
        res = compare(dag, platform, seed=seed + i)
        ms = {k: (None if s is None else s.makespan) for k, s in res.items()}
        rows.append({"tasks": len(dag), "cp": dag_stats(dag)["critical_path_ms"], **ms})
    h4k_k8s = [speedup(r["k8s-default"], r["heft4k"]) for r in rows if r["k8s-default"] is not None]
    hk_k8s = [speedup(r["k8s-default"], r["heft-k8s"]) for r in rows if r["k8s-default"] is not None]
    h4k_hk = [speedup(r["heft-k8s"], r["heft4k"]) for r in rows]
    h4k_dpe = [speedup(r["dpe"], r["heft4k"]) for r in rows]
    h4k_ideal = [speedup(r["heft4k"], r["heft-ideal"]) for r in rows]
    dpe_wins = [speedup(r["heft4k"], r["dpe"]) for r in rows if r["dpe"] < r["heft4k"] - 1e-9]
    unsched = [r["tasks"] for r in rows if r["k8s-default"] is None]
    print("\n== Scheduler comparison (Figs. 4.16-4.18), speedup of the first over the second ==")
    print(f"  HEFT4K vs default K8s   {fmt(q(h4k_k8s))}   thesis: avg 43%, >=40% (<=32 tasks), >100% larger")
    print(f"     (as makespan reduction: mean {statistics.fmean([1 - 100 / (100 + s) for s in h4k_k8s]) * 100:.1f}%)")
    print(f"  HEFT on K8s vs K8s      {fmt(q(hk_k8s))}   thesis: avg 17.7%")
    print(f"  HEFT4K vs HEFT on K8s   {fmt(q(h4k_hk))}   thesis: avg ~13%")
    print(f"  HEFT4K vs DPE           {fmt(q(h4k_dpe))}   thesis: avg 16%, up to 40% above 64 tasks")
    share = len(dpe_wins) / len(rows)
    print(
        f"  DPE faster in {share:.0%} of DAGs, by {statistics.fmean(dpe_wins) if dpe_wins else 0:.1f}% on average"
        "   thesis: <25% of cases, ~4%"
    )
    print(f"  ideal HEFT vs HEFT4K    {fmt(q(h4k_ideal))}   (what the lack of synchronisation costs HEFT4K)")
    sizes = f"sizes {min(unsched, default=0)}..{max(unsched, default=0)}"
    print(
        f"  default K8s unschedulable for {len(unsched)} DAGs ({sizes}); thesis: fails > 160 tasks "
        "(thesis scenario: the model's 160-pod limit is the thesis' number)"
    )
    print("  per DAG size (Figs. 4.16 / 4.17): HEFT4K vs K8s | HEFT4K vs DPE | HEFT4K vs HEFT on K8s (medians, n)")
    bins: dict[str, dict[str, list[float]]] = defaultdict(lambda: defaultdict(list))
    for r in rows:
        b = bins[size_bin(r["tasks"])]
        if r["k8s-default"] is not None:
            b["k8s"].append(speedup(r["k8s-default"], r["heft4k"]))
        b["dpe"].append(speedup(r["dpe"], r["heft4k"]))
        b["hk"].append(speedup(r["heft-k8s"], r["heft4k"]))
    for name in sorted(bins):
        b = bins[name]
        k8s = (
            f"{statistics.median(b['k8s']):7.1f}% (q3 {q(b['k8s'])['q3']:6.1f}%)"
            if b["k8s"]
            else "  unschedulable     "
        )
        print(
            f"    {name}: {k8s} | {statistics.median(b['dpe']):6.1f}% | {statistics.median(b['hk']):6.1f}%"
            f"   n={len(b['dpe'])}"
        )
    print("  Fig. 4.18 heatmap, mean HEFT4K vs HEFT on K8s by size (rows) x critical-path tercile (columns):")
    cps = sorted(r["cp"] for r in rows)
    cuts = [cps[len(cps) // 3], cps[2 * len(cps) // 3]]
    heat: dict[tuple[int, int], list[float]] = defaultdict(list)
    for r in rows:
        heat[(min(3, (r["tasks"] - 1) // 128), sum(r["cp"] > c for c in cuts))].append(
            speedup(r["heft-k8s"], r["heft4k"])
        )
    print(f"    critical path: <= {cuts[0]:.0f} ms | <= {cuts[1]:.0f} ms | longer")
    for size in range(4):
        cells = [heat.get((size, c), []) for c in range(3)]
        text = " | ".join(f"{statistics.fmean(c):6.1f}% (n={len(c):3d})" if c else "     -          " for c in cells)
        print(f"    {size * 128 + 1:3d}-{size * 128 + 128:3d} tasks: {text}")
    summary = {
        "heft4k_vs_k8s": q(h4k_k8s),
        "heftk8s_vs_k8s": q(hk_k8s),
        "heft4k_vs_heftk8s": q(h4k_hk),
        "heft4k_vs_dpe": q(h4k_dpe),
        "dpe_wins_share": share,
        "dpe_win_margin": statistics.fmean(dpe_wins) if dpe_wins else 0.0,
        "ideal_vs_heft4k": q(h4k_ideal),
        "k8s_unschedulable": len(unsched),
    }
    return summary, rows


# ---- 3. remapping (Fig. 4.19) ---------------------------------------------------------------------
def remapping(cases: list[tuple[TaskGraph, object]], seed: int, losses: int = 5) -> dict:
    rng = random.Random(seed)
    step: dict[tuple[int, bool], list[float]] = defaultdict(list)
    cumulative: dict[tuple[int, bool], list[float]] = defaultdict(list)
    modes: dict[int, dict[str, int]] = defaultdict(lambda: defaultdict(int))
    times: list[tuple[int, float]] = []
    for dag, platform in cases:
        plan = heft4k(dag, platform)
        start = prev = run_heft4k(dag, platform, plan).makespan
        small = len(dag) < 96
        for k in range(1, losses + 1):
            node = rng.choice([p.id for p in platform.processors])
            r = remap(plan, dag, platform, [node])
            platform, plan = platform.without([node]), r.schedule
            now = run_heft4k(dag, platform, plan).makespan
            step[(k, small)].append(speedup(prev, now))
            cumulative[(k, small)].append(speedup(start, now))
            modes[k][r.mode] += 1
            times.append((len(dag), r.elapsed_ms))
            prev = now
    print("\n== Event-driven remapping after successive node losses (Fig. 4.19), theta = 20% ==")
    print(
        "  lost | DAGs < 96 tasks: vs previous, vs 6 nodes | DAGs >= 96 tasks: vs previous, vs 6 nodes | partial/total"
    )
    out = {}
    for k in range(1, losses + 1):
        cells = []
        for small in (True, False):
            s, c = step[(k, small)], cumulative[(k, small)]
            cells.append(f"{statistics.fmean(s):6.1f}% {statistics.fmean(c):6.1f}%" if s else "   -       -   ")
            out[f"{k}_{'small' if small else 'large'}"] = {"step": q(s), "cumulative": q(c)}
        print(f"  {k:4d} | {cells[0]:>28} | {cells[1]:>28} | {modes[k]['partial']}/{modes[k]['total']}")
    print("  thesis: about -6% per lost node below 96 tasks (1-3 lost); larger DAGs above -15% with 1-2 lost;")
    print("          3 lost about -20%; 4-5 lost about -25%")
    ms = [t for _, t in times]
    big = [t for n, t in times if n >= 400]
    print(
        f"  remap computation: median {statistics.median(ms):.1f} ms, max {max(ms):.1f} ms"
        + (f"; DAGs >= 400 tasks: median {statistics.median(big):.1f} ms, max {max(big):.1f} ms" if big else "")
        + "   thesis: a few ms"
    )
    out["remap_ms"] = {"median": statistics.median(ms), "max": max(ms)}
    return out


# ---- 4. threshold calibration (Fig. 3.31) --------------------------------------------------------
def calibration(cases: list[tuple[TaskGraph, object]], seed: int) -> dict:
    def simulated(dag, platform, schedule):
        return run_heft4k(dag, platform, schedule).makespan

    points = calibration_points(cases, seed=seed, evaluate=simulated)
    print("\n== Threshold calibration (Fig. 3.31): partial vs from-scratch remap after one node loss ==")
    buckets: dict[int, list[float]] = defaultdict(list)
    for p in points:
        buckets[min(5, int(p.lost_share * 10))].append(p.gap * 100)
    for b in sorted(buckets):
        label = f"{b * 10:2d}-{b * 10 + 10:2d}%" if b < 5 else ">=50% "
        g = buckets[b]
        print(f"  lost rank {label}: n={len(g):4d}  mean gap {statistics.fmean(g):6.1f}%  max {max(g):6.1f}%")
    result = calibrate_threshold(points, delta=0.10)
    strict = calibrate_threshold(points, delta=0.10, statistic="p90")
    marginal = calibrate_threshold(points, delta=0.10, statistic="marginal")
    for row in result["curve"]:
        print(
            f"    theta {row['threshold']:.2f}: {row['cases']:4d} partial cases, gap mean {row['mean_gap'] * 100:5.1f}%"
            f", 90th percentile {row['p90_gap'] * 100:5.1f}%; the {row['step_cases']:3d} cases this step adds: "
            f"mean {row['step_mean_gap'] * 100:5.1f}%"
        )
    print(
        f"  calibrated threshold for delta = 10%: {result['threshold']} by the mean gap, {strict['threshold']} by "
        f"the 90th percentile, {marginal['threshold']} stepping until delta is exceeded   thesis: ~20%"
    )
    return {
        "threshold": result["threshold"],
        "threshold_p90": strict["threshold"],
        "threshold_marginal": marginal["threshold"],
        "curve": result["curve"],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dags", type=int, default=150)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", help="write the figures to this file")
    ap.add_argument(
        "--costs",
        choices=["per-node", "per-task"],
        default="per-node",
        help="task costs drawn per (task, node) (spec reading, default) or once per task (homogeneous nodes)",
    )
    args = ap.parse_args()
    t0 = time.perf_counter()
    results: dict = {"example": example()}
    rng = random.Random(args.seed)
    cases = []
    for _ in range(args.dags):
        platform = random_cluster(rng)
        cases.append((random_dag(rng, [p.id for p in platform.processors], cost_model=args.costs), platform))
    stats = corpus_stats(dag for dag, _ in cases)
    print(f"\n== Corpus: {args.dags} DAGs (seed {args.seed}, {args.costs} costs) vs Table 4.28 (avg / median) ==")
    for k, v in stats.items():
        t = TABLE_4_28[k]
        print(
            f"  {k:18} ours {v['avg']:7.1f} / {v['median']:7.1f}   thesis {t[2]:7.1f} / {t[3]:7.1f}"
            f"   range ours {v['min']:.4g}..{v['max']:.4g}, thesis {t[0]:g}..{t[1]:g}"
        )
    results["corpus"] = stats
    t1 = time.perf_counter()
    results["comparison"], rows = comparison(cases, args.seed)
    t2 = time.perf_counter()
    results["remap"] = remapping(cases, args.seed)
    t3 = time.perf_counter()
    results["calibration"] = calibration(cases, args.seed)
    t4 = time.perf_counter()
    took = f"comparison {t2 - t1:.0f} s, remapping {t3 - t2:.0f} s, calibration {t4 - t3:.0f} s"
    print(f"\n(times: {took}, total {t4 - t0:.0f} s)")
    if args.json:
        Path(args.json).write_text(json.dumps({**results, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
