"""HEFT at fleet scale: 100,000 tasks on 64 processors, time, peak memory and growth (run on demand:
``python benchmarks/heft_scale.py [--procs 64] [--sizes 12500,25000,50000,100000]``).

Inputs: the layered DAGs and related machines of ``benchmarks/heft_vs_saga.py`` (CCR 1, one entry and one
exit task), with the task/edge limits raised for the run. Times are CPU seconds of this process (the
machine is shared, wall time is printed beside them) for each phase: compiling the DAG to index lists,
upward ranks (Eq. 2.1), the priority list, the insertion-based list scheduler. Peak memory is the traced
Python allocation of one ``heft()`` call (tracemalloc, a separate run) and the process's max RSS.
"""

from __future__ import annotations

import argparse
import itertools
import resource
import time
import tracemalloc

from _bench import fit_exponent, table
from heft_vs_saga import instance

from continuum.engine.core import limits
from continuum.engine.device.heft import compile_problem, compiled_ranks, heft, priority_list, schedule_list

GOAL_S, GOAL_MIB = 10.0, 1024.0


def phases(dag, platform) -> tuple[list[float], float]:
    cpu0, wall0 = time.process_time(), time.perf_counter()
    marks = [cpu0]
    prob = compile_problem(dag, platform)
    marks.append(time.process_time())
    ranks = compiled_ranks(prob)
    marks.append(time.process_time())
    order = priority_list(prob, ranks)
    marks.append(time.process_time())
    schedule_list(prob, order)
    marks.append(time.process_time())
    return [b - a for a, b in itertools.pairwise(marks)], time.perf_counter() - wall0


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--procs", type=int, default=64)
    ap.add_argument("--sizes", default="12500,25000,50000,100000")
    args = ap.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    rows, totals = [], []
    with limits.override(tasks=max(sizes) + 2, edges=10 * max(sizes), cost_entries=max(sizes) * args.procs * 2):
        for n in sizes:
            dag, platform = instance(n, args.procs, 0)
            cpu0 = time.process_time()
            schedule = heft(dag, platform)
            total = time.process_time() - cpu0
            parts, wall = phases(dag, platform)
            totals.append(total)
            rows.append([n, args.procs, len(dag.edges), total, wall, *parts, schedule.makespan])
            del schedule
        print(f"HEFT (insertion), layered DAGs, {args.procs} related processors; CPU seconds unless marked wall")
        headers = ["tasks", "procs", "edges", "heft() s", "phases wall s", "compile s", "ranks s", "order s",
                   "schedule s", "makespan"]  # fmt: skip
        print(table(headers, rows))
        if len(sizes) > 1:
            print(f"growth exponent in tasks: {fit_exponent(sizes, totals):.2f}")
        tracemalloc.start()
        heft(dag, platform)
        peak = tracemalloc.get_traced_memory()[1] / 2**20
        tracemalloc.stop()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    n = sizes[-1]
    print(f"{n} tasks: heft() {totals[-1]:.2f} s CPU = {totals[-1] / GOAL_S:.2f} of the {GOAL_S:g} s goal; "
          f"peak traced memory {peak:.0f} MiB = {peak / GOAL_MIB:.2f} of the 1 GiB goal; "
          f"process max RSS {rss:.0f} MiB (DAG and platform included)")  # fmt: skip


if __name__ == "__main__":
    main()
