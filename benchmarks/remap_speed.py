"""How fast Algorithm 2 remaps a 1000-task DAG on a 50-node cluster after one node fails (goal: < 100 ms).

Run: ``python benchmarks/remap_speed.py [--tasks 1000] [--nodes 50] [--failures 10] [--seed 0]``.
A Table 4.28-like DAG (:mod:`continuum.engine.heft4k.synthetic`) on a full mesh of 2-CPU nodes with U[500, 1000]
Mbit/s links is mapped once with HEFT4K (look-ahead); then single nodes fail one at a time (each time from
the original mapping) and the remap time is measured around the whole of :func:`remap` (removing the node,
re-routing the cluster, deciding, mapping, niceness), side by side with mapping from scratch.
"""

from __future__ import annotations

import argparse
import random
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from continuum.engine.heft4k.heft4k import heft4k
from continuum.engine.heft4k.remap import remap
from continuum.engine.heft4k.synthetic import random_cluster, random_dag


def timed(fn, *args, **kwargs):
    t = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, (time.perf_counter() - t) * 1000.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tasks", type=int, default=1000)
    ap.add_argument("--nodes", type=int, default=50)
    ap.add_argument("--failures", type=int, default=10)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    platform = random_cluster(rng, nodes=args.nodes)
    dag = random_dag(rng, [p.id for p in platform.processors], n=args.tasks)
    print(f"DAG: {len(dag)} tasks, {len(dag.edges)} edges; cluster: {args.nodes} nodes x 2 CPUs, full mesh")
    plan, t_la = timed(heft4k, dag, platform)
    _, t_plain = timed(heft4k, dag, platform, lookahead=False)
    print(f"HEFT4K from scratch: look-ahead {t_la:.0f} ms (makespan {plan.makespan:.1f}), plain HEFT {t_plain:.0f} ms")
    auto, partial, total = [], [], []
    for node in rng.sample([p.id for p in platform.processors], args.failures):
        r = remap(plan, dag, platform, [node])
        auto.append(r.elapsed_ms)
        p = remap(plan, dag, platform, [node], mode="partial")
        partial.append(p.elapsed_ms)
        t = remap(plan, dag, platform, [node], mode="total")
        total.append(t.elapsed_ms)
        print(
            f"  lose {node:>4}: {len(r.lost):3d} tasks lost ({r.lost_share:5.1%} of the rank) -> {r.mode:7} "
            f"in {r.elapsed_ms:6.1f} ms; makespan {r.makespan_before:.1f} -> {r.makespan_after:.1f} "
            f"(partial {p.makespan_after:.1f} in {p.elapsed_ms:.1f} ms, total {t.makespan_after:.1f} in "
            f"{t.elapsed_ms:.0f} ms)"
        )
    for name, xs in (("Algorithm 2 (decided)", auto), ("forced partial", partial), ("forced total", total)):
        print(f"{name:22}: median {statistics.median(xs):7.1f} ms, max {max(xs):7.1f} ms over {len(xs)} failures")
    ratio = statistics.median(total) / statistics.median(partial)
    print(f"partial remap is {ratio:.0f}x faster than remapping from scratch (median); goal: partial < 100 ms")


if __name__ == "__main__":
    main()
