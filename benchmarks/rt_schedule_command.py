"""The ``rt_schedule`` command a user runs against the engine under it, in the same run (issue 29).

Writes a synthetic ``continuum.cluster/v1`` file of ``--nodes`` nodes and a ``continuum.rtset/v1`` file of
``--pods`` RT containers (the generator of ``benchmarks/rt_kube_scale.py``: a WCET on every RT node), then
times, side by side:

* **engine**: ``rt_kube_vec.schedule`` on the parsed containers and nodes, in this process;
* **command (in process)**: ``Command().run_from_argv(... --json)`` with stdout to a file: reading and
  validating both files, deciding, writing the JSON (what the command costs past Django's start);
* **command (process)**: ``python manage.py rt_schedule RTSET --cluster FILE --json > out`` as a user runs
  it, from exec to exit (interpreter and Django start included), with its peak memory (max RSS);

and prints decisions/s per wall and per CPU second for each, the output's size, the peak memory against the
500 MiB goal, whether the command's choices are the engine's (node and score of every container), and
``--explain POD``'s cost for one pending pod (its full per-node verdict). Then a cProfile of the in-process
command's hottest entries.

    python benchmarks/rt_schedule_command.py [--nodes 5000] [--pods 1000] [--seed 1] [--profile]
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import pstats
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from benchmarks._bench import ROOT, loadavg, table
from benchmarks.rt_kube_scale import make_nodes, make_pods
from continuum.engine.rtkube import rt_kube_vec
from continuum.engine.rtkube.rt_model import cluster_to_dict, rtset_to_dict

GOAL_RATE = 2000.0  # decisions/s end to end, issue 29
GOAL_MIB = 500.0


def clock(fn):
    """(result, wall s, CPU s of this process)."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - wall, time.process_time() - cpu


# The child's own peak memory: forked from this (large) process, its max RSS would count this one's pages at
# the fork; a small launcher process forks it instead and reports its usage (wait4) on stderr.
_LAUNCH = (
    "import json, os, subprocess, sys; c = subprocess.Popen(sys.argv[1:]); _, s, u = os.wait4(c.pid, 0); "
    "sys.stderr.write(chr(10) + json.dumps([u.ru_utime + u.ru_stime, u.ru_maxrss, os.waitstatus_to_exitcode(s)]))"
)


def run_process(argv: list[str], out_path: Path) -> tuple[float, float, float, int]:
    """(wall s, CPU s, max RSS MiB, exit status) of a child running ``argv`` with stdout to ``out_path``."""
    start = time.perf_counter()
    with out_path.open("wb") as out:
        done = subprocess.run([sys.executable, "-c", _LAUNCH, *argv], stdout=out, stderr=subprocess.PIPE, cwd=ROOT)
    wall = time.perf_counter() - start
    cpu, rss_kib, status = json.loads(done.stderr.decode().strip().splitlines()[-1])
    return wall, cpu, rss_kib / 1024, status


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--nodes", type=int, default=5000)
    p.add_argument("--pods", type=int, default=1000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--profile", action="store_true", help="cProfile the in-process command")
    args = p.parse_args()
    os.environ.setdefault("DJANGO_SETTINGS_MODULE", "continuum.settings")
    import django

    django.setup()
    from apps.realtime.management.commands.rt_schedule import Command

    n, m = args.nodes, args.pods
    nodes = make_nodes(n, random.Random(args.seed * 1000 + n))
    pods = make_pods(m, nodes, random.Random(args.seed * 7 + m + n))
    tmp = Path(tempfile.mkdtemp(prefix="rt-schedule-bench-"))
    cluster, rtset = tmp / "cluster.json", tmp / "rtset.json"
    cluster.write_text(json.dumps(cluster_to_dict(nodes)))
    rtset.write_text(json.dumps(rtset_to_dict(pods)))
    print(f"{n} nodes x {m} RT containers; inputs {cluster.stat().st_size / 2**20:.1f} MiB + "
          f"{rtset.stat().st_size / 2**20:.1f} MiB; load average {loadavg()}", flush=True)  # fmt: skip

    plan, e_wall, e_cpu = clock(lambda: rt_kube_vec.schedule(pods, nodes))
    engine = {d.item: (d.node, d.score) for d in plan.decisions}

    argv = [str(rtset), "--cluster", str(cluster), "--json"]
    out_in = tmp / "in-process.json"

    def in_process() -> None:
        with out_in.open("w") as fh:
            cmd = Command(stdout=fh)
            cmd.run_from_argv(["manage.py", "rt_schedule", *argv])

    _, c_wall, c_cpu = clock(in_process)
    doc = json.loads(out_in.read_text())
    chosen = {x["container"]: (x["node"], x["score"]) for x in doc["placements"]}
    chosen.update({x["container"]: (None, None) for x in doc["pending"]})
    same = chosen == engine

    out_proc = tmp / "process.json"
    p_wall, p_cpu, p_rss, status = run_process([sys.executable, "manage.py", "rt_schedule", *argv], out_proc)
    same_proc = status == 0 and json.loads(out_proc.read_text())["placements"] == doc["placements"]
    boot_wall, boot_cpu, boot_rss, _ = run_process([sys.executable, "manage.py", "help", "rt_schedule"], tmp / "h")

    pending = [x["container"] for x in doc["pending"]]
    explain_row = None
    if pending:
        out_x = tmp / "explain.json"
        x_wall, x_cpu, x_rss, x_status = run_process(
            [sys.executable, "manage.py", "rt_schedule", *argv, "--explain", pending[0]], out_x
        )
        if x_status == 0:
            verdicts = json.loads(out_x.read_text())["explain"]
            explain_row = (pending[0], len(verdicts), x_wall, x_cpu, x_rss, out_x.stat().st_size / 2**20)

    rows = [
        ["engine (rt_kube_vec.schedule)", e_wall, e_cpu, m / e_wall, m / e_cpu, "-", "-"],
        ["command in process (parse+decide+JSON)", c_wall, c_cpu, m / c_wall, m / c_cpu, "-",
         f"{out_in.stat().st_size / 2**20:.2f}"],
        ["command process (exec..exit)", p_wall, p_cpu, m / p_wall, m / p_cpu, f"{p_rss:.0f}",
         f"{out_proc.stat().st_size / 2**20:.2f}"],
        ["  of which interpreter+Django start", boot_wall, boot_cpu, "-", "-", f"{boot_rss:.0f}", "-"],
    ]  # fmt: skip
    print(table(["path", "wall s", "CPU s", "dec/s wall", "dec/CPU-s", "max RSS MiB", "out MiB"], rows))
    placed = len(doc["placements"])
    print(f"placed {placed}, pending {len(pending)}; command's choices == engine's: {'yes' if same else 'NO'}"
          f" (process: {'yes' if same_proc else 'NO'})")  # fmt: skip
    print(f"goal: >= {GOAL_RATE:.0f} decisions/s end to end -> in process {m / c_wall:.0f}/s wall "
          f"({m / c_cpu:.0f}/CPU-s); whole process {m / p_wall:.0f}/s wall; "
          f"< {GOAL_MIB:.0f} MiB -> max RSS {p_rss:.0f} MiB")  # fmt: skip
    if explain_row:
        name, count, x_wall, x_cpu, x_rss, x_mib = explain_row
        print(f"--explain {name}: {count} node verdicts, {x_wall:.2f} s wall, {x_cpu:.2f} s CPU, "
              f"max RSS {x_rss:.0f} MiB, {x_mib:.2f} MiB of JSON")  # fmt: skip
    print(f"load average after: {loadavg()}")

    if args.profile:
        prof = cProfile.Profile()
        prof.enable()
        in_process()
        prof.disable()
        buf = io.StringIO()
        pstats.Stats(prof, stream=buf).sort_stats("tottime").print_stats(14)
        print("\ncProfile of the command in process (own time):")
        print("\n".join(line for line in buf.getvalue().splitlines() if line.strip())[-2600:])


if __name__ == "__main__":
    main()
