"""Online STL monitoring throughput: Continuum's Boolean monitor vs rtamt (and mstlo) on the response
pattern ``(x >= 7) -> F[0,b](y >= 7)`` at b = 10, 100, 1000, with identical verdicts checked.

    python benchmarks/stl_vs_rtamt.py [--samples N] [--bounds 10,100,1000] [--venv DIR]

The peers are installed by this script into a throw-away virtual environment (default
``/tmp/continuum-stl-peers``) and run there in a subprocess on the same trace; never vendored.
Each sample updates both signals at ts = sample index (ms), the unit of the interval in all three tools.
Ours: ``Monitor("G(x >= 7 -> F[0,b](y >= 7))")`` fed event by event (push x, push y, evaluate).
rtamt: ``StlDiscreteTimeSpecification`` online (``pastify`` + ``update`` per sample) for the timing.
mstlo: ``Monitor(..., semantics="DelayedQualitative")``, ``update_batch`` per sample.
Verdicts are compared on every sample that both tools decided. Times: the fastest of --repeat runs.

rtamt's verdicts are taken from its offline evaluation of the same trace: its online (pastified)
monitor of this formula does not give the offline verdicts. Its output at sample i is
``x[i-2b] >= 7 -> (y >= 7 somewhere in [i-b, i])``: the antecedent is delayed by 2b and the consequent
window by b, so it checks the window [t+b, t+2b] for the instance at t (found by fitting the online
output against shifted windows; exact at b = 10). The script prints how many online verdicts differ.
"""

from __future__ import annotations

import argparse
import json
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from continuum.engine.verification.stl_monitor import Monitor

PEERS = ["rtamt==0.4.10", "antlr4-python3-runtime==4.7"]
OPTIONAL = ["mstlo-python==0.2.2"]

PEER_RUNNER = r"""
import json, sys, time
trace = json.load(open(sys.argv[1]))
b = int(sys.argv[2])
repeat = int(sys.argv[4])
xs, ys = trace["x"], trace["y"]
n = len(xs)
out = {}
try:
    import rtamt
    dt = float("inf")
    for _ in range(repeat):
        spec = rtamt.StlDiscreteTimeSpecification()
        spec.declare_var("x", "float")
        spec.declare_var("y", "float")
        spec.spec = f"(x>=7) -> (eventually[0:{b}](y>=7))"
        spec.parse()
        spec.pastify()
        rob = []
        t0 = time.perf_counter()
        for i in range(n):
            rob.append(spec.update(i, [("x", xs[i]), ("y", ys[i])]))
        dt = min(dt, time.perf_counter() - t0)
    lag = 0
    while lag < n and rob[lag] == float("inf"):
        lag += 1
    online = {i: rob[i + lag] >= 0 for i in range(n - lag)}
    # offline (whole trace) semantics, the reference for the verdict comparison
    spec = rtamt.StlDiscreteTimeSpecification()
    spec.declare_var("x", "float")
    spec.declare_var("y", "float")
    spec.spec = f"(x>=7) -> (eventually[0:{b}](y>=7))"
    spec.parse()
    offline = {t: r >= 0 for t, r in spec.evaluate({"time": list(range(n)), "x": xs, "y": ys}) if t < n - b}
    out["rtamt"] = {"seconds": dt, "lag": lag, "verdicts": offline, "online_verdicts": online}
except Exception as exc:  # the peer may be missing
    out["rtamt"] = {"error": repr(exc)}
try:
    import mstlo_python as mstlo
    dt = float("inf")
    for _ in range(repeat):
        phi = mstlo.parse_formula(f"(x >= 7) -> F[0, {b}](y >= 7)")
        mon = mstlo.Monitor(phi, semantics="DelayedQualitative")
        verdicts = {}
        t0 = time.perf_counter()
        for i in range(n):
            res = mon.update_batch([("x", xs[i], float(i)), ("y", ys[i], float(i))])
            for t, v in res.verdicts():
                verdicts[int(t)] = bool(v)
        dt = min(dt, time.perf_counter() - t0)
    out["mstlo"] = {"seconds": dt, "verdicts": verdicts}
except Exception as exc:
    out["mstlo"] = {"error": repr(exc)}
json.dump(out, open(sys.argv[3], "w"))
"""


def ensure_venv(venv: Path) -> Path:
    python = venv / "bin" / "python"
    if not python.exists():
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    have = subprocess.run([str(python), "-m", "pip", "freeze"], capture_output=True, text=True).stdout.lower()
    need = [p for p in PEERS if p.lower() not in have]
    if need:
        subprocess.run([str(python), "-m", "pip", "install", "-q", *need], check=True)
    for opt in OPTIONAL:
        if opt.lower() not in have:
            r = subprocess.run([str(python), "-m", "pip", "install", "-q", opt], capture_output=True, text=True)
            if r.returncode:
                print(f"note: {opt} did not install: {r.stderr.strip().splitlines()[-1:]}")
    return python


def walk(rng: random.Random, n: int) -> list[float]:
    v, out = rng.uniform(0, 10), []
    for _ in range(n):
        v = min(10.0, max(0.0, v + rng.uniform(-1.0, 1.0)))
        out.append(v)
    return out


def ours(xs: list[float], ys: list[float], b: int, repeat: int) -> tuple[float, dict[int, bool]]:
    dt = float("inf")
    for _ in range(repeat):
        m = Monitor(f"G(x >= 7 -> F[0,{b}](y >= 7))")
        violations = []
        push, evaluate = m.push, m.evaluate
        t0 = time.perf_counter()
        for i in range(len(xs)):
            push("x", xs[i], i)
            push("y", ys[i], i)
            violations += evaluate()
        dt = min(dt, time.perf_counter() - t0)
    violations += m.flush()
    failed = {v.instance_start for v in violations}
    pending = set(m.pending_starts())
    return dt, {i: i not in failed for i in range(len(xs)) if i not in pending}


def compare(a: dict[int, bool], b: dict) -> tuple[int, int]:
    common = [i for i in a if str(i) in b]
    return len(common), sum(1 for i in common if a[i] != b[str(i)])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=20000)
    parser.add_argument("--bounds", default="10,100,1000")
    parser.add_argument("--venv", default="/tmp/continuum-stl-peers")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per tool; the fastest counts")
    args = parser.parse_args()
    python = ensure_venv(Path(args.venv))
    rng = random.Random(args.seed)
    n = args.samples
    xs, ys = walk(rng, n), walk(rng, n)
    print(f"trace: {n} samples, 2 signals, random walks in [0, 10] (seed {args.seed})")
    print(
        f"{'b':>6} {'ours us/sample':>15} {'rtamt':>10} {'mstlo':>10} {'rtamt/ours':>11} {'mstlo/ours':>11}  verdicts"
    )
    with tempfile.TemporaryDirectory() as tmp:
        trace_path = Path(tmp) / "trace.json"
        trace_path.write_text(json.dumps({"x": xs, "y": ys}))
        runner = Path(tmp) / "peer_runner.py"
        runner.write_text(PEER_RUNNER)
        for b in [int(v) for v in args.bounds.split(",")]:
            result_path = Path(tmp) / f"peers-{b}.json"
            cmd = [str(python), str(runner), str(trace_path), str(b), str(result_path), str(args.repeat)]
            subprocess.run(cmd, check=True)
            peers = json.loads(result_path.read_text())
            dt, verdicts = ours(xs, ys, b, args.repeat)
            us = dt / n * 1e6
            cells, notes = [], []
            for name in ("rtamt", "mstlo"):
                peer = peers[name]
                if "error" in peer:
                    cells.append(("n/a", "n/a"))
                    notes.append(f"{name}: {peer['error']}")
                    continue
                peer_us = peer["seconds"] / n * 1e6
                common, mismatches = compare(verdicts, peer["verdicts"])
                cells.append((f"{peer_us:.2f}", f"{peer_us / us:.1f}x"))
                kind = " offline" if name == "rtamt" else ""
                notes.append(f"{name}{kind}: {common} compared, {mismatches} differ")
                if "online_verdicts" in peer:
                    common, mismatches = compare(verdicts, peer["online_verdicts"])
                    notes.append(f"rtamt online: {mismatches} of {common} differ")
            print(
                f"{b:>6} {us:>15.2f} {cells[0][0]:>10} {cells[1][0]:>10} {cells[0][1]:>11} {cells[1][1]:>11}  "
                + "; ".join(notes)
            )


if __name__ == "__main__":
    main()
