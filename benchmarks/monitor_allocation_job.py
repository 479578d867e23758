"""The monitor allocation a user starts (``POST /api/v1/allocations/``, the ``allocate_monitors`` job) against the
engine under it, side by side (issue 29).

Fleets of ``benchmarks/milp_scaling.py`` (robot-local: every monitor reads its own robot's topics; cross-robot:
10 % also read another robot's), ``--monitors`` x ``--nodes``. For each: ``allocate()`` with the default work
budget (``DEFAULT_WORK_LIMIT`` branch-and-bound nodes, no clock), then the request's contract and the job's
handler on the same statistics, in a throw-away database (``<DATABASE_URL's name>_alloc_bench``): CPU and wall
time, status, objective, relative gap and bound, and whether the job's allocation is the engine's (it must be:
the budget is work, not time). ``--repeat`` runs the job again to show the same allocation under the load of
the moment. Prints the load average.

    python benchmarks/monitor_allocation_job.py [--monitors 1000] [--nodes 20] [--seed N]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from benchmarks._bench import loadavg, table, throwaway_database
from benchmarks.milp_scaling import fleet


def clock(fn):
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--monitors", type=int, default=1000)
    p.add_argument("--nodes", type=int, default=20)
    p.add_argument("--seed", type=int, default=None, help="default: monitors + nodes, as milp_scaling.py")
    p.add_argument("--repeat", type=int, default=1, help="extra runs of the job on the same statistics")
    p.add_argument("--fleets", default="robot-local,cross-robot", help="which fleets (comma-separated)")
    args = p.parse_args()
    with throwaway_database("_alloc_bench"):
        run(args)


def run(args: argparse.Namespace) -> None:
    import django

    django.setup()
    from django.core.management import call_command

    from apps.jobs.models import Job
    from apps.jobs.registry import HANDLERS
    from apps.tenancy.models import Fleet
    from apps.verification.models import AllocationRun
    from apps.verification.serializers import AllocationRequestSerializer
    from continuum.engine.verification.monitor_milp import DEFAULT_WORK_LIMIT, allocate

    call_command("migrate", verbosity=0)
    owner, _ = Fleet.objects.get_or_create(slug="alloc-bench", defaults={"name": "alloc-bench"})
    print(f"{args.monitors} monitors x {args.nodes} nodes, work budget {DEFAULT_WORK_LIMIT} nodes per solve; "
          f"load average {loadavg()}", flush=True)  # fmt: skip
    rows = []
    chosen = {f.strip() for f in args.fleets.split(",")}
    for label, cross in (("robot-local", 0.0), ("cross-robot", 0.1)):
        if label not in chosen:
            continue
        seed = args.seed if args.seed is not None else args.monitors + args.nodes
        doc = fleet(args.monitors, args.nodes, seed, uniform=False, cross=cross)
        engine, e_wall, e_cpu = clock(lambda doc=doc: allocate(doc, work_limit=DEFAULT_WORK_LIMIT, time_limit=math.inf))
        rows.append([f"{label}: engine", e_wall, e_cpu, engine.status, engine.objective, engine.gap,
                     engine.objective * (1 - engine.gap), "-"])  # fmt: skip
        request = AllocationRequestSerializer(data={"stats": doc})
        assert request.is_valid(), request.errors
        for attempt in range(1 + args.repeat):
            job = Job.objects.create(kind="allocate_monitors", fleet=owner, arguments=request.job_arguments())
            (summary, _), j_wall, j_cpu = clock(lambda job=job: HANDLERS["allocate_monitors"](job, lambda *a: None))
            stored = AllocationRun.objects.get(pk=summary["allocation_run"]).result["allocation"]
            same = stored == engine.allocation
            rows.append([f"{label}: job{' again' if attempt else ''}", j_wall, j_cpu, summary["status"],
                         summary["objective"], summary["gap"], summary["bound"], "yes" if same else "NO"])  # fmt: skip
        print(f"  {label} done; load average {loadavg()}", flush=True)
    print(table(["path", "wall s", "CPU s", "status", "objective", "gap", "bound", "same as engine"], rows))
    print(f"load average after: {loadavg()}")


if __name__ == "__main__":
    main()
