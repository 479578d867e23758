"""Tables 4.30-4.31 for real: deadline tasks on this machine's kernel, next to the thesis and our simulator.

    sudo python benchmarks/rt_deadline_experiment.py [--seconds 8] [--seed 0] [--exec-high 1.0] [--json FILE]

What runs. Each RT container of Table 4.30 is one process of ``benchmarks/rt_deadline_worker.c`` (a
cyclicdeadline-like periodic job, compiled here with gcc) started by the node agent
(``python -m continuum.agent run --runtime-ms WCET --deadline-ms P --period-ms P -- worker job ...``): the kernel
admits or refuses it (EBUSY: Eq. 2.4), SIGXCPU counts its runtime overruns, the worker counts its missed
deadlines. Each job's demand is U(0.3, --exec-high) x WCET of CPU time, the simulator's model. The one non-RT
container is a memory stress (a 64 MiB buffer written line by line), SCHED_OTHER.

Scaled to this machine (2 CPUs): the thesis' nodes were J (Jetson, 8 cores, class C, 7.6 of RT bandwidth) and I
(16-core server for A and B); here each is one CPU, an exclusive cpuset partition (cgroup v1 ``cpuset`` with
``cpu_exclusive`` and the root's ``sched_load_balance`` off: each partition is its own root domain, so the
kernel's admission allows 0.95 of one CPU in each, as it allowed 7.6 on J). Task counts are divided by 8
(Table 4.30's 32/24/16 -> 4/3/2, 16/24/32 -> 2/3/4); periods and deadlines stay 24.2 / 18.1 / 14.5 ms; the
WCET is 2.8 ms instead of 2.9 so that the first deployment's A and B containers fit one CPU's 0.95 (0.927) as
they fitted I in the thesis. The thesis' third machine R (a PC without an RT kernel, for the stress) has no
CPU of its own here: RT-Kube's stress runs in the root cpuset at SCHED_OTHER.

Configurations: "all on one node" = the thesis' K3S standard (every container on J, in a random creation
order, the kernel admitting in that order); "RT-Kube" = the placement of continuum.engine.rtkube.rt_kube.schedule on
the same three nodes (a container it cannot place stays Pending: it never reaches the kernel). The simulator
(continuum.engine.rtkube.rt_sim, with benchmarks/rt_kube_thesis.py's calibration: 5 % overrun probability per job
with a stress container on the node) runs the same sets, placements and duration.

The machine is shared: what other processes do on the two CPUs is part of the measurement (SCHED_DEADLINE
preempts them). While the experiment runs (about 4 x --seconds), the root cpuset does not load-balance; it is
restored at the end (also on Ctrl-C or an error).
"""

from __future__ import annotations

import argparse
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(HERE))

from rt_kube_thesis import PERIODS, THESIS_431  # noqa: E402

from continuum.agent.sched import DeadlineParams, rt_bandwidth, set_deadline  # noqa: E402
from continuum.engine.rtkube import rt_kube  # noqa: E402
from continuum.engine.rtkube.rt_model import cluster_from_dict, rtset_from_dict  # noqa: E402
from continuum.engine.rtkube.rt_sim import SimParams, kube_default_placer, rt_kube_placer, simulate  # noqa: E402

CPUSET = Path("/sys/fs/cgroup/cpuset")
WORKER_SRC = HERE / "rt_deadline_worker.c"
WCET_MS = 2.8
MIXES = {"1st": (4, 3, 2), "2nd": (2, 3, 4)}  # Table 4.30 / 8
THESIS_MIXES = {"1st": (32, 24, 16), "2nd": (16, 24, 32)}
CONFIGS = ("all on one node", "RT-Kube")


# ---- the machine ---------------------------------------------------------------------------------------------
def build_worker() -> Path:
    out = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "continuum" / "rt_deadline_worker"
    if not out.exists() or out.stat().st_mtime < WORKER_SRC.stat().st_mtime:
        out.parent.mkdir(parents=True, exist_ok=True)
        subprocess.run(["gcc", "-O2", "-Wall", "-o", str(out), str(WORKER_SRC)], check=True)
    return out


def _cpus(text: str) -> list[int]:
    out = []
    for part in text.strip().split(","):
        if part:
            lo, _, hi = part.partition("-")
            out.extend(range(int(lo), int(hi or lo) + 1))
    return out


class Partitions:
    """Two exclusive cpuset partitions (J: the first CPU, I: the second), each its own root domain."""

    def __init__(self) -> None:
        self.dirs: dict[str, Path] = {}
        self.balance: str | None = None

    def __enter__(self) -> Partitions:
        if not (CPUSET / "cpuset.cpus").exists():
            sys.exit("needs the cgroup v1 cpuset hierarchy at /sys/fs/cgroup/cpuset (cgroup v2 partitions: "
                     "cpuset.cpus.partition=root, not implemented here)")  # fmt: skip
        cpus = _cpus((CPUSET / "cpuset.effective_cpus").read_text())
        if len(cpus) < 2:
            sys.exit(f"needs two CPUs, this machine has {cpus}")
        mems = (CPUSET / "cpuset.mems").read_text().strip()
        self.balance = (CPUSET / "cpuset.sched_load_balance").read_text().strip()
        try:
            for name, cpu in (("J", cpus[0]), ("I", cpus[1])):
                d = CPUSET / f"continuum-rt-{name}"
                d.mkdir(exist_ok=True)
                self.dirs[name] = d
                (d / "cpuset.cpus").write_text(str(cpu))
                (d / "cpuset.mems").write_text(mems)
                (d / "cpuset.cpu_exclusive").write_text("1")
            (CPUSET / "cpuset.sched_load_balance").write_text("0")
        except BaseException:
            self.__exit__()
            raise
        return self

    def __exit__(self, *exc: object) -> None:
        if self.balance is not None:
            (CPUSET / "cpuset.sched_load_balance").write_text(self.balance)
        for d in self.dirs.values():
            for _ in range(50):  # its processes may still be exiting
                try:
                    d.rmdir()
                    break
                except OSError:
                    time.sleep(0.1)

    def enter(self, node: str) -> None:
        """Move the calling process into node's partition (R: stays in the root cpuset)."""
        if node in self.dirs:
            (self.dirs[node] / "cgroup.procs").write_text(str(os.getpid()))


def admission_cap(parts: Partitions, node: str = "J") -> float:
    """The largest bandwidth the kernel admits for one task in an empty partition (bisection to 0.001, each probe
    a forked process that enters the partition, asks for SCHED_DEADLINE and exits)."""

    def admitted(bw: float) -> bool:
        pid = os.fork()
        if pid == 0:
            code = 1
            try:
                parts.enter(node)
                set_deadline(DeadlineParams(round(bw * 10_000_000), 10_000_000, 10_000_000))
                code = 0
            finally:
                os._exit(code)
        return os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]) == 0

    lo, hi = 0.0, 1.0
    if admitted(hi):
        return hi
    while hi - lo > 0.001:
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if admitted(mid) else (lo, mid)
    return lo


# ---- the sets ------------------------------------------------------------------------------------------------
def container_docs(mix: tuple[int, int, int], seed: int) -> list[dict]:
    """The scaled Table 4.30 set in a random creation order (``arrival``), plus the stress."""
    docs = []
    for cls, n in zip("ABC", mix, strict=True):
        for i in range(n):
            docs.append({"name": f"{cls}{i}", "criticality": cls, "period": PERIODS[cls], "deadline": PERIODS[cls],
                         "wcet": {"J": WCET_MS, "I": WCET_MS, "R": WCET_MS}, "stateless": True})  # fmt: skip
    docs.append({"name": "stress", "criticality": None, "stateless": True})
    order = list(range(len(docs)))
    random.Random(seed).shuffle(order)
    for doc, pos in zip(docs, order, strict=True):
        doc["arrival"] = pos * 0.01
    return sorted(docs, key=lambda d: d["arrival"])


def nodes(rt_taints: bool):
    extra = {} if rt_taints else {"taints": []}
    return cluster_from_dict({"nodes": [
        {"name": "J", "cpu": 1, "rt": True, "criticality": "C", **extra},
        {"name": "I", "cpu": 1, "rt": True, "criticality": "A", **extra},
        {"name": "R", "cpu": 1, "rt": False},
    ]})  # fmt: skip


def placement(config: str, docs: list[dict], seed: int) -> dict[str, str | None]:
    containers = rtset_from_dict({"containers": docs})
    if config == "RT-Kube":
        plan = rt_kube.schedule(containers, nodes(True))
    else:
        plan = rt_kube.kube_default(containers, nodes(False), rng=random.Random(seed), pin="J")
    placed = plan.placed()
    return {d["name"]: placed.get(d["name"]) for d in docs}


# ---- real runs -----------------------------------------------------------------------------------------------
def _deadline_child(agent: subprocess.Popen) -> bool:
    """True once the agent's command runs as a deadline task; False when the agent ended (refused)."""
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        if agent.poll() is not None:
            return False
        try:
            kids = Path(f"/proc/{agent.pid}/task/{agent.pid}/children").read_text().split()
            if kids and os.sched_getscheduler(int(kids[0])) & 0xFF == 6:
                return True
        except OSError:
            pass
        time.sleep(0.005)
    return False


def run_real(docs, where, seconds, seed, worker, parts, high=1.0) -> dict[str, dict]:
    """Start the containers in creation order (each admitted or refused before the next starts); once all are
    there, let their jobs begin together (a go file) and wait for them."""
    # The agent runs each job as nobody (it drops root): the worker and the go file must be within its reach.
    scratch = Path(tempfile.mkdtemp(prefix="rt-deadline-"))
    scratch.chmod(0o755)
    go = scratch / "go"
    shutil.copy2(worker, scratch / "worker")
    worker = scratch / "worker"
    procs: dict[str, subprocess.Popen] = {}
    out: dict[str, dict] = {}
    for i, d in enumerate(docs):
        node = where[d["name"]]
        if node is None:
            out[d["name"]] = {"status": "pending"}
            continue
        if d["criticality"] is None:
            cmd = [str(worker), "stress", "64", str(seconds), str(go)]
        else:
            p_us = round(d["period"] * 1000)
            cmd = [sys.executable, "-m", "continuum.agent", "run", "--runtime-ms", str(WCET_MS), "--deadline-ms",
                   str(d["period"]), "--period-ms", str(d["period"]), "--container", d["name"], "--json", "--",
                   str(worker), "job", str(round(WCET_MS * 1000)), str(p_us), str(p_us), str(seconds),
                   str(seed * 1000 + i), str(go), str(high)]  # fmt: skip
        proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                preexec_fn=lambda node=node: parts.enter(node))  # fmt: skip
        procs[d["name"]] = proc
        if d["criticality"] is not None:
            _deadline_child(proc)
    go.touch()
    for name, proc in procs.items():
        stdout, stderr = proc.communicate(timeout=seconds + 60)
        docs_out = [json.loads(ln) for ln in stdout.splitlines() if ln.startswith("{")]
        if name == "stress":
            out[name] = {"status": "running", **(docs_out[0] if docs_out else {})}
            continue
        agent = docs_out[-1] if docs_out else {}
        job = next((x for x in docs_out if "jobs" in x), {})
        if agent.get("kernel_rejected"):
            out[name] = {"status": "rejected", "agent_status": proc.returncode}
        elif proc.returncode != 0 or not job:
            raise RuntimeError(f"{name}: agent status {proc.returncode}: {stderr.strip()[-300:]}")
        else:
            out[name] = {"status": "running", "jobs": job["jobs"], "missed": job["missed"],
                         "overruns": agent["overruns"], "max_lateness_us": job["max_lateness_us"]}  # fmt: skip
    go.unlink()
    go.parent.rmdir()
    return out


# ---- tables --------------------------------------------------------------------------------------------------
def by_class(docs, results: dict[str, dict]) -> dict[str, dict]:
    """Table 4.31's columns: rejected, % missed by the running tasks, and with the rejected ones at 100 %."""
    out = {}
    for cls in "ABC":
        members = [results[d["name"]] for d in docs if d["criticality"] == cls]
        running = [r for r in members if r["status"] == "running"]
        rejected = sum(r["status"] == "rejected" for r in members)
        pending = sum(r["status"] == "pending" for r in members)
        jobs = sum(r["jobs"] for r in running)
        missed = sum(r["missed"] for r in running)
        run_pct = 100.0 * missed / jobs if jobs else 0.0
        placed = len(running) + rejected
        out[cls] = {"containers": len(members), "rejected": rejected, "pending": pending, "jobs": jobs,
                    "missed": missed, "overruns": sum(r.get("overruns", 0) for r in running),
                    "missed_running_pct": run_pct,
                    "missed_total_pct": (len(running) * run_pct + rejected * 100.0) / placed if placed else 0.0,
                    }  # fmt: skip
    return out


def simulated(config, docs, seconds, seed, high=1.0) -> dict[str, dict]:
    containers = rtset_from_dict({"containers": docs})
    placer = rt_kube_placer() if config == "RT-Kube" else kube_default_placer(seed, pin="J")
    params = SimParams(horizon_ms=seconds * 1000.0, seed=seed, p_overrun_stress=0.05, p_overrun_non_rt_kernel=0.02,
                       stressors=frozenset({"stress"}), exec_high=high)  # fmt: skip
    r = simulate(containers, nodes(config == "RT-Kube"), placer, params)
    out = r.by_class()
    for cls, row in out.items():
        row["overruns"] = sum(s.overruns for s in r.containers.values() if s.criticality == cls and not s.rejected)
    return out


def fmt_row(label: str, rows: dict[str, dict], where: str = "") -> str:
    rej = "/".join(f"{rows[c]['rejected']:g}" for c in "ABC")
    pend = "/".join(f"{rows[c].get('pending', 0):g}" for c in "ABC")
    miss = "  ".join(f"{c} {rows[c]['missed_running_pct']:4.1f}-{rows[c]['missed_total_pct']:5.1f}" for c in "ABC")
    ovr = "/".join(str(rows[c]["overruns"]) if "overruns" in rows[c] else "-" for c in "ABC")
    return f"    {label:<22} {where:<22} {rej:<9} {pend:<9} {miss:<44} {ovr}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=int, default=8, help="length of each run (default 8)")
    ap.add_argument("--seed", type=int, default=0, help="creation order and job demands")
    ap.add_argument("--exec-high", type=float, default=1.0, help="jobs run U(0.3, this) x WCET (default 1.0)")
    ap.add_argument("--json", help="write every figure to this file")
    args = ap.parse_args()
    if os.geteuid() != 0:
        sys.exit("run as root: SCHED_DEADLINE and cpuset partitions need it")
    worker = build_worker()
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))  # leave through Partitions.__exit__
    t0 = time.monotonic()
    results: dict = {}
    with Partitions() as parts:
        print(f"partitions: J = CPU {parts.dirs['J'].joinpath('cpuset.cpus').read_text().strip()}, "
              f"I = CPU {parts.dirs['I'].joinpath('cpuset.cpus').read_text().strip()} (exclusive cpusets, "
              f"root sched_load_balance off); R = root cpuset; {args.seconds} s per run, seed {args.seed}, "
              f"jobs U(0.3, {args.exec_high}) x WCET")  # fmt: skip
        cap = admission_cap(parts)
        results["admission_cap"] = {"measured": cap, "sched_rt_ratio": rt_bandwidth()}
        print(
            f"kernel admission in one partition (1 CPU), measured: {cap:.3f} of the CPU for deadline tasks; "
            f"sched_rt_runtime_us/sched_rt_period_us = {rt_bandwidth():.3f} (RT-Kube's and rt_sim's threshold)"
        )
        for dep, mix in MIXES.items():
            docs = container_docs(mix, args.seed)
            results[dep] = {}
            for config in CONFIGS:
                where = placement(config, docs, args.seed)
                real = run_real(docs, where, args.seconds, args.seed, worker, parts, args.exec_high)
                results[dep][config] = {
                    "placement": where,
                    "real": by_class(docs, real),
                    "real_containers": real,
                    "sim": simulated(config, docs, args.seconds, args.seed, args.exec_high),
                }
    print("\nrejected A/B/C = refused by the kernel (EBUSY); pending = kept out of the kernel by RT-Kube;")
    print("missed % = deadlines missed by the running tasks - with the rejected ones counted at 100 % (Table 4.31);")
    print("overruns = SIGXCPU counted by the agent (real) / CBS budget exhaustions (simulator)")
    for dep, mix in MIXES.items():
        tm = THESIS_MIXES[dep]
        print(f"\n{dep} deployment: here A {mix[0]}, B {mix[1]}, C {mix[2]} + stress (thesis: A {tm[0]}, B {tm[1]}, "
              f"C {tm[2]} + stress)")  # fmt: skip
        head = f"{'missed % (running - +rejected)':<44}"
        print(f"    {'config':<22} {'source':<22} {'rejected':<9} {'pending':<9} {head} overruns")
        for config in CONFIGS:
            row = results[dep][config]
            counts: dict[str, dict[str, int]] = {}
            for name, node in row["placement"].items():
                cls = name[0] if name != "stress" else "oth"
                counts.setdefault(cls, {}).setdefault(str(node), 0)
                counts[cls][str(node)] += 1
            place = " ".join(f"{c}:" + ",".join(f"{n}({v})" for n, v in sorted(d.items())) for c, d in counts.items())
            print(f"  {config}: {place}")
            print(fmt_row("", row["real"], "real (this machine)"))
            print(fmt_row("", row["sim"], "simulator (rt_sim)"))
            thesis = THESIS_431[dep]["K3S standard" if config == "all on one node" else "RT-Kube"]
            trow = {c: {"rejected": thesis[c][0], "missed_running_pct": thesis[c][1], "missed_total_pct": thesis[c][2]}
                    for c in "ABC"}  # fmt: skip
            print(fmt_row("", trow, "thesis Table 4.31"))
    print("\nper container (real): " + "; ".join(
        f"{dep}/{cfg}: " + ", ".join(
            f"{n} {r['status'][:3]}" + (f" {r['missed']}/{r['jobs']} ovr {r['overruns']}" if "jobs" in r else "")
            for n, r in results[dep][cfg]["real_containers"].items() if n != "stress")
        for dep in MIXES for cfg in CONFIGS))  # fmt: skip
    print("\nreal vs simulator, kernel rejections (A+B+C) and deadlines missed by running tasks:")
    for dep in MIXES:
        for config in CONFIGS:
            real, sim = results[dep][config]["real"], results[dep][config]["sim"]
            rj = [sum(x[c]["rejected"] for c in "ABC") for x in (real, sim)]
            jobs = [sum(x[c]["jobs"] for c in "ABC") for x in (real, sim)]
            missed = [sum(x[c]["missed"] for c in "ABC") for x in (real, sim)]
            pct = [100.0 * m / j if j else 0.0 for m, j in zip(missed, jobs, strict=True)]
            print(f"  {dep} {config:<16} rejected real {rj[0]} sim {rj[1]}{'  <- differs' if rj[0] != rj[1] else ''}; "
                  f"missed real {pct[0]:.1f}% sim {pct[1]:.1f}% of running jobs")  # fmt: skip
    print(f"\n(total {time.monotonic() - t0:.1f} s)")
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=2, default=str))


if __name__ == "__main__":
    main()
