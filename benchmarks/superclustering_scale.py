"""Super-clustering at fleet scale against today's code, side by side (run on demand:
``python benchmarks/superclustering_scale.py [--nodes 500] [--sizes 625,1250,2500,5000]``).

Random workloads from ``tests/engine/containers/superclustering_reference.random_instance`` (mixed archs,
taints, affinities, ~4 bandwidth neighbours per container). Times: the plan with its metrics (what
``superclustering()`` returns; per-node verdicts are built when first read) and, separately, reading every
verdict (``to_dict``), which the old code always paid. Prints the growth exponent in containers.
"""

from __future__ import annotations

import argparse
import time
import tracemalloc

from _bench import ROOT, fit_exponent, table  # noqa: F401  (puts the repo on sys.path)

from continuum.engine.containers.superclustering import superclustering
from tests.engine.containers import superclustering_reference as ref


def timed(fn, repeats: int = 1):
    """(result, least CPU seconds over ``repeats`` runs)."""
    best, out = float("inf"), None
    for _ in range(repeats):
        start = time.process_time()
        out = fn()
        best = min(best, time.process_time() - start)
    return out, best


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--nodes", type=int, default=500)
    ap.add_argument("--sizes", default="625,1250,2500,5000")
    ap.add_argument("--no-reference", action="store_true", help="skip today's code (minutes at 5,000)")
    args = ap.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    rows, fast_t, ref_t = [], [], []
    superclustering(*ref.random_instance(200, args.nodes, seed=0))  # warm-up: imports, caches
    for n in sizes:
        wl, cl = ref.random_instance(n, args.nodes, seed=n)
        plan, t_fast = timed(lambda wl=wl, cl=cl: superclustering(wl, cl), repeats=3)
        _, t_explain = timed(lambda plan=plan: plan.to_dict())
        fast_t.append(t_fast)
        if args.no_reference:
            rows.append([n, args.nodes, t_fast, t_explain, "-", "-", "-"])
            continue
        old, t_ref = timed(lambda wl=wl, cl=cl: ref.superclustering(wl, cl))
        ref_t.append(t_ref)
        same = old.placed() == plan.placed() and old.metrics == plan.metrics
        rows.append([n, args.nodes, t_fast, t_explain, t_ref, f"{t_ref / t_fast:.0f}x", "yes" if same else "NO"])
    print(f"super-clustering, {args.nodes} nodes, CPU seconds (process time) on this machine")
    print(table(["containers", "nodes", "new s", "+ all verdicts s", "today s", "speed-up", "same plan"], rows))
    if len(sizes) > 1:
        print(f"growth exponent in containers: new {fit_exponent(sizes, fast_t):.2f}", end="")
        print(f", today {fit_exponent(sizes, ref_t):.2f}" if ref_t else "")
    wl, cl = ref.random_instance(sizes[-1], args.nodes, seed=sizes[-1])
    tracemalloc.start()
    superclustering(wl, cl)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    print(f"peak traced memory of the new plan at {sizes[-1]} containers: {peak / 2**20:.1f} MiB")


if __name__ == "__main__":
    main()
