"""The in-process benchmarks at two git revisions, run interleaved, one table of before/after figures (issue 15:
"nothing gets slower elsewhere: the existing benchmarks' figures before and after, from one run each").

    python benchmarks/compare_revisions.py [--old ff4db15] [--new HEAD] [--benchmarks orb_frames remap_speed ...]
        [--python PATH] [--timeout 900] [--logs DIR] [--list]

Each revision is checked out (detached) into a temporary ``git worktree`` under /tmp, removed at the end. For
every benchmark, the old revision's script runs, then the new one's (old, new, old, new ... so drift of the
shared machine falls on both), same arguments (``DEFAULTS``: the benchmark's quick settings, a few minutes at
most), same python (the shared venv's by default), the worktree as working directory and first on PYTHONPATH
(checked: ``continuum`` must import from that worktree), ``BENCH_DB`` set per revision for those that read it.

Figures per run:

* CPU s: user + sys CPU time of the whole child process tree (``os.wait4``'s resource usage: the child and
  every descendant it waited for). Load-independent on a shared machine, and needs no parsing: the primary
  figure, and the after/before ratio is of it.
* wall s, peak RSS (MiB) of the child, and the 1-minute load average at the start and end of the run.
* the benchmark's own headline figure(s) where its output is easy to parse (``HEADLINES``), e.g. the scheduling
  call's time that the benchmark itself measures. These are mostly wall times of one call (noisy under load).

Caveat: a benchmark that stops a solver at a wall-clock limit spends less CPU when the machine is loaded. So do
milp_scaling's time-limited cells and, at ff4db15, kairos_monitors (0.9 s of MILP per simulated period; since
59385af its budget is branch-and-bound nodes, reproducible, and its solves run to optimality: more CPU by design).

A benchmark whose script is missing at the old revision is reported as ``new`` (its figures at the new one
only). Benchmarks that need a Kubernetes cluster, a browser or a server under load are not in the default list.
Benchmarks that install their peers (saga, rtamt) into /tmp venvs get them installed before the first timed run,
so the install is charged to neither side.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_PYTHON = Path(sys.executable)

# name -> arguments. Chosen so that each run takes at most a few minutes of CPU on the shared 2-core machine.
DEFAULTS: dict[str, list[str]] = {
    "orb_frames": [],
    "remap_speed": ["--failures", "5"],
    "ros_clustering": [],
    "milp_scaling": ["--quick"],
    "kairos_monitors": [],
    "rt_kube_thesis": ["--quick"],
    "heft4k_thesis": ["--dags", "30"],
    "fig329_search": ["1", "ABCDEFGH"],
    "heft_vs_saga": ["--quick"],
    "stl_vs_rtamt": ["--samples", "5000", "--repeat", "1"],
    "heft_scale": ["--sizes", "5000,12500"],
    "superclustering_scale": ["--sizes", "625,1250", "--no-reference"],
    "rt_kube_scale": ["--nodes", "1000", "5000", "--pods", "100", "1000", "--ref-pods", "10"],
}

# Not run unless named: heft_vs_saga's CPU time is saga's (minutes for its 5,000-task DAG, in the peer venv);
# fig329_search is a seeded search of ~12 CPU-s per restart until it reproduces the fixture (minutes). The HEFT and
# HEFT4K code they run did not change between ff4db15 and issue 15's work (orb_frames, heft4k_thesis and
# remap_speed run it too).
OPT_IN = {"heft_vs_saga", "fig329_search"}

# Python run in the new revision's worktree before any timed run: installs a benchmark's peers into its venv.
PREPARE: dict[str, str] = {
    "heft_vs_saga": (
        "import sys; sys.path.insert(0, 'benchmarks'); from _bench import ensure_venv; "
        "from heft_vs_saga import SAGA_VENV; ensure_venv(SAGA_VENV, 'anrg-saga==2.0.2', 'saga')"
    ),
    "stl_vs_rtamt": (
        "import sys; sys.path.insert(0, 'benchmarks'); from pathlib import Path; "
        "from stl_vs_rtamt import ensure_venv; ensure_venv(Path('/tmp/continuum-stl-peers'))"
    ),
}


def _floats(pattern: str, text: str) -> list[float]:
    return [float(m) for m in re.findall(pattern, text, flags=re.MULTILINE)]


def _mean(values: Sequence[float]) -> float | None:
    return sum(values) / len(values) if values else None


def _row_value(text: str, row: str, column: int) -> float | None:
    """The ``column``-th whitespace-separated cell of the first line starting with ``row`` (after indentation)."""
    for line in text.splitlines():
        cells = line.split()
        if cells and cells[0] == row and len(cells) > column:
            try:
                return float(cells[column])
            except ValueError:
                return None
    return None


def _headline_orb_frames(text: str) -> dict[str, float | None]:
    # "10 batched frames" table: algorithm makespan latency buffers "time ms" ...
    section = text.split("10 batched frames", 1)[-1] if "10 batched frames" in text else ""
    return {"heft 10 frames ms": _row_value(section, "heft", 4), "xeft 10 frames ms": _row_value(section, "xeft", 4)}


def _headline_remap_speed(text: str) -> dict[str, float | None]:
    return {
        "mean partial remap ms": _mean(_floats(r"-> partial in\s+([\d.]+) ms", text)),
        "heft4k scratch ms": next(iter(_floats(r"look-ahead ([\d.]+) ms", text)), None),
    }


def _headline_ros_clustering(text: str) -> dict[str, float | None]:
    # "  N method ... ms note" rows; Listing 3.20's own time is the penultimate numeric column.
    listing = _floats(r"^\s*\d+ Listing 3\.20\s+\d+\s+\d+\s+[\d,]+\s+[\d.]+%\s+([\d.]+)", text)
    return {
        "Listing 3.20 total ms": sum(listing) if listing else None,
        "super-clustering Table 4.26 ms": next(
            iter(_floats(r"super-clustering\s+inter-node.*\(([\d.]+) ms\)", text)), None
        ),
    }


def _headline_milp_scaling(text: str) -> dict[str, float | None]:
    local = _floats(r"^robot-local .*?\s([\d.]+) ms\s+optimal", text)
    return {
        "case study 1 mean ms": next(iter(_floats(r"case study 1 .*?mean ([\d.]+) ms", text)), None),
        "robot-local solves total ms": sum(local) if local else None,
    }


def _headline_rt_kube_thesis(text: str) -> dict[str, float | None]:
    rows = re.findall(r"^\s*(\d+) nodes, (\d+) containers: ([\d.]+) s", text, flags=re.MULTILINE)
    return {f"throughput {n} nodes x {c} s": float(sec) for n, c, sec in rows}


def _headline_heft4k_thesis(text: str) -> dict[str, float | None]:
    return {
        "remap median ms": next(iter(_floats(r"remap computation: median ([\d.]+) ms", text)), None),
        "total s (printed)": next(iter(_floats(r"\(times: .*total ([\d.]+) s\)", text)), None),
    }


def _headline_kairos_monitors(text: str) -> dict[str, float | None]:
    out: dict[str, float | None] = {}
    for block in re.split(r"^=== ", text, flags=re.MULTILINE)[1:]:
        name = block.split(":", 1)[0].split("-")[0]  # "synthetic", "rb"
        out[f"{name} simulated s"] = next(iter(_floats(r"simulated in ([\d.]+) s", block)), None)
        out[f"{name} MILP mean ms"] = next(iter(_floats(r"^\s*milp_mean_ms\s+([\d.]+)", block)), None)
    return out


def _headline_stl_vs_rtamt(text: str) -> dict[str, float | None]:
    rows = re.findall(r"^\s*(\d+)\s+([\d.]+)\s+\S+\s+\S+\s+\S+x", text, flags=re.MULTILINE)
    return {f"ours us/sample b={b}": float(us) for b, us in rows}


def _headline_heft_scale(text: str) -> dict[str, float | None]:
    rows = re.findall(r"^\s*(\d+)\s+\d+\s+\d+\s+([\d.]+)\s", text, flags=re.MULTILINE)
    return {f"heft() CPU s, {n} tasks": float(sec) for n, sec in rows}


def _headline_superclustering_scale(text: str) -> dict[str, float | None]:
    rows = re.findall(r"^\s*(\d+)\s+\d+\s+([\d.]+)\s+([\d.]+)\s", text, flags=re.MULTILINE)
    return {f"plan CPU s, {n} containers": float(sec) for n, sec, _ in rows}


def _headline_rt_kube_scale(text: str) -> dict[str, float | None]:
    rows = re.findall(r"^\s*(\d+) nodes x (\d+) pods: .*?, (\d+)/CPU-s", text, flags=re.MULTILINE)
    return {f"decisions/CPU-s {n} x {p}": float(rate) for n, p, rate in rows}


HEADLINES: dict[str, Callable[[str], dict[str, float | None]]] = {
    "stl_vs_rtamt": _headline_stl_vs_rtamt,
    "heft_scale": _headline_heft_scale,
    "superclustering_scale": _headline_superclustering_scale,
    "rt_kube_scale": _headline_rt_kube_scale,
    "kairos_monitors": _headline_kairos_monitors,
    "orb_frames": _headline_orb_frames,
    "remap_speed": _headline_remap_speed,
    "ros_clustering": _headline_ros_clustering,
    "milp_scaling": _headline_milp_scaling,
    "rt_kube_thesis": _headline_rt_kube_thesis,
    "heft4k_thesis": _headline_heft4k_thesis,
}


@dataclass
class Run:
    """One benchmark run at one revision."""

    returncode: int
    cpu_s: float
    wall_s: float
    maxrss_mib: float
    load_start: float
    load_end: float
    output: str
    headline: dict[str, float | None] = field(default_factory=dict)


def load1() -> float:
    return float(Path("/proc/loadavg").read_text().split()[0])


def run_benchmark(python: Path, tree: Path, name: str, args: Sequence[str], env: dict[str, str], timeout: float) -> Run:
    """Run ``benchmarks/<name>.py`` of ``tree``; the child tree's CPU time from ``os.wait4``."""
    with tempfile.TemporaryFile(mode="w+") as out:
        load_start, start = load1(), time.perf_counter()
        proc = subprocess.Popen(
            [str(python), f"benchmarks/{name}.py", *args], cwd=tree, env=env, stdout=out, stderr=subprocess.STDOUT
        )
        deadline = start + timeout
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.perf_counter() > deadline:
                proc.kill()
                pid, status, usage = os.wait4(proc.pid, 0)
                break
            time.sleep(0.05)
        proc.returncode = os.waitstatus_to_exitcode(status)  # reaped here: Popen must not wait for it again
        wall = time.perf_counter() - start
        out.seek(0)
        text = out.read()
    parse = HEADLINES.get(name)
    headline = parse(text) if parse and proc.returncode == 0 else {}
    return Run(
        returncode=proc.returncode,
        cpu_s=usage.ru_utime + usage.ru_stime,
        wall_s=wall,
        maxrss_mib=usage.ru_maxrss / 1024.0,
        load_start=load_start,
        load_end=load1(),
        output=text,
        headline=headline,
    )


def git(*args: str, cwd: Path = ROOT) -> str:
    return subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True, text=True).stdout.strip()


def child_env(tree: Path, label: str) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(tree)
    env["BENCH_DB"] = f"continuum_bench_compare_{label}"
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    return env


def check_imports(python: Path, tree: Path, env: dict[str, str]) -> None:
    """``continuum`` must come from ``tree``, not from an installed copy or another checkout."""
    got = subprocess.run(
        [str(python), "-c", "import continuum; print(continuum.__file__)"],
        cwd=tree,
        env=env,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    if not Path(got).resolve().is_relative_to(tree.resolve()):
        raise SystemExit(f"continuum imports from {got}, not from {tree}")


def fmt(value: float | None, digits: int = 3) -> str:
    if value is None:
        return "-"
    return f"{value:.{digits}g}" if abs(value) < 10**digits else f"{value:.0f}"


def ratio(old: float | None, new: float | None) -> str:
    if old is None or new is None or old <= 0:
        return "-"
    return f"{new / old:.2f}"


def render(results: dict[str, tuple[Run | None, Run | None]], args_by_name: dict[str, list[str]]) -> str:
    """The before/after table: one line per benchmark (CPU of the child tree), then one per headline figure it
    printed (indented; times unless named a rate), then each benchmark's arguments."""
    headers = ["benchmark", "CPU s before", "CPU s after", "after/before", "wall s b/a", "RSS MiB b/a", "load b/a"]
    rows: list[list[str]] = []
    for name, (old, new) in results.items():
        if new is None:
            rows.append([name, "-", "-", "missing at new", "-", "-", "-"])
            continue
        if old is None:
            cells = ["new", fmt(new.cpu_s), "new", f"- / {fmt(new.wall_s)}", f"- / {new.maxrss_mib:.0f}"]
            loads = f"- / {new.load_start:.1f}-{new.load_end:.1f}"
        else:
            cells = [
                fmt(old.cpu_s),
                fmt(new.cpu_s),
                ratio(old.cpu_s, new.cpu_s),
                f"{fmt(old.wall_s)} / {fmt(new.wall_s)}",
                f"{old.maxrss_mib:.0f} / {new.maxrss_mib:.0f}",
            ]
            loads = f"{old.load_start:.1f}-{old.load_end:.1f} / {new.load_start:.1f}-{new.load_end:.1f}"
        failed = [f"{side} exit {r.returncode}" for side, r in (("before", old), ("after", new)) if r and r.returncode]
        if failed:
            cells[2] = f"FAILED ({', '.join(failed)})"
        rows.append([name, *cells, loads])
        for key, value in new.headline.items():
            before = old.headline.get(key) if old else None
            rows.append([f"  {key}", fmt(before) if old else "new", fmt(value), ratio(before, value), "", "", ""])
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]
    lines = ["  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(r, widths, strict=True)))
             for r in [headers, *rows]]  # fmt: skip
    lines.append("")
    lines += [f"{name}: {' '.join(args_by_name.get(name, [])) or '(no arguments)'}" for name in results]
    return "\n".join(line.rstrip() for line in lines)


def parse_args(argv: Sequence[str] | None = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    p.add_argument("--old", default="ff4db15", help="the 'before' revision (default ff4db15)")
    p.add_argument("--new", default="HEAD", help="the 'after' revision (default HEAD)")
    p.add_argument(
        "--benchmarks",
        nargs="+",
        default=[n for n in DEFAULTS if n not in OPT_IN],
        metavar="NAME",
        help=f"default: all of {', '.join(DEFAULTS)} but {', '.join(sorted(OPT_IN))}",
    )
    p.add_argument("--python", type=Path, default=DEFAULT_PYTHON, help="interpreter (default: this one)")
    p.add_argument("--timeout", type=float, default=900.0, help="seconds per run before it is killed")
    p.add_argument("--logs", type=Path, help="write each run's output to DIR/<name>.<old|new>.txt")
    p.add_argument("--list", action="store_true", help="print the benchmarks and their arguments, run nothing")
    args = p.parse_args(argv)
    unknown = [n for n in args.benchmarks if n not in DEFAULTS]
    if unknown:
        p.error(f"unknown benchmark(s) {', '.join(unknown)}; known: {', '.join(DEFAULTS)}")
    if args.timeout <= 0:
        p.error("--timeout must be positive")
    if not args.list and not args.python.exists():
        p.error(f"--python {args.python} does not exist")
    return args


def main(argv: Sequence[str] | None = None) -> int:
    args = parse_args(argv)
    if args.list:
        for name in args.benchmarks:
            print(name, " ".join(DEFAULTS[name]))
        return 0
    try:
        revs = {
            "old": git("rev-parse", "--verify", f"{args.old}^{{commit}}"),
            "new": git("rev-parse", "--verify", f"{args.new}^{{commit}}"),
        }
    except subprocess.CalledProcessError as exc:
        print(f"compare_revisions: unknown revision: {exc.stderr.strip()}", file=sys.stderr)
        return 2
    base = Path(tempfile.mkdtemp(prefix="continuum-compare-", dir="/tmp"))
    trees = {label: base / label for label in revs}
    results: dict[str, tuple[Run | None, Run | None]] = {}
    try:
        for label, rev in revs.items():
            git("worktree", "add", "--detach", str(trees[label]), rev)
        envs = {label: child_env(trees[label], label) for label in revs}
        for label in revs:
            check_imports(args.python, trees[label], envs[label])
        print(f"before: {args.old} = {revs['old']}\nafter:  {args.new} = {revs['new']}")
        print(
            f"python: {args.python}; worktrees under {base}; load at start {Path('/proc/loadavg').read_text().strip()}"
        )
        for name in args.benchmarks:
            if name in PREPARE and (trees["new"] / "benchmarks" / f"{name}.py").exists():
                subprocess.run([str(args.python), "-c", PREPARE[name]], cwd=trees["new"], env=envs["new"], check=True)
        for name in args.benchmarks:
            runs: dict[str, Run | None] = {}
            for label in revs:  # old, then new
                if not (trees[label] / "benchmarks" / f"{name}.py").exists():
                    runs[label] = None
                    continue
                run = run_benchmark(args.python, trees[label], name, DEFAULTS[name], envs[label], args.timeout)
                runs[label] = run
                status = "ok" if run.returncode == 0 else f"exit {run.returncode}"
                print(
                    f"{name:22} {label}: {status}, CPU {run.cpu_s:.2f} s, wall {run.wall_s:.1f} s, "
                    f"load {run.load_start:.2f}-{run.load_end:.2f}",
                    flush=True,
                )
                if args.logs:
                    args.logs.mkdir(parents=True, exist_ok=True)
                    (args.logs / f"{name}.{label}.txt").write_text(run.output)
            results[name] = (runs["old"], runs["new"])
    finally:
        for tree in trees.values():
            if tree.exists():
                subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT, capture_output=True)
        subprocess.run(["git", "worktree", "prune"], cwd=ROOT, capture_output=True)
        shutil.rmtree(base, ignore_errors=True)
    print()
    print(render(results, {n: DEFAULTS[n] for n in results}))
    print(f"\nload at end: {Path('/proc/loadavg').read_text().strip()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
