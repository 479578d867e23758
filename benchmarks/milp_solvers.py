"""The monitor-allocation MILP (Eqs. 3.21-3.22) of the cross-robot fleets given to other solvers.

    python benchmarks/milp_solvers.py [--sizes 500x5,500x10,1000x20]
        [--fleets uniform,heterogeneous] [--solvers highs,scip,cpsat,cpsat-cp] [--time-limit 60]
        [--checkpoints 1,10,60] [--start] [--workers 2] [--cpsat-params 'linearization_level:2']

Question: does any solver prove optimality of the "covers" model on the cross-robot fleets of
benchmarks/milp_scaling.py (``fleet(m, n, seed=m+n, uniform, cross=0.1)``) where HiGHS cannot?

The model is the exact one HiGHS solves in ``allocate`` (``_classes`` + ``_build(..., formulation="covers")``
of continuum/engine/verification/monitor_milp.py: class counts n[c,j], topic receptions y[k,j],
group indicators z[g,j], relief and host cover families w, hard capacities; variable lower bounds 0).
It is written once to an .npz file, and each solver runs on it in its own subprocess (ortools ships
its own HiGHS whose symbols clash with highspy's, so they cannot share a process):

  * ``highs``: highspy with the options of ``monitor_milp._solve`` (1 thread, mip_rel_gap 1e-4,
    HIGHS_OPTIONS); progress from its MIP callbacks.
  * ``scip``: PySCIPOpt on the same rows (1 thread, limits/gap 1e-4); it is re-optimised up to each
    checkpoint (SCIP continues a solve stopped by its time limit).
  * ``cpsat``: OR-Tools CP-SAT on the same rows, ``--workers`` workers (default 2: the machine has 2
    cores). CP-SAT needs integers: the objective is scaled by 1000 (delays have 2 decimals, ε = 1e-3
    becomes 1, both exact; the 1e-6 cost per reception is dropped) and each row by the smallest power of
    10 (<= 1e6) that makes its coefficients and bounds integral (CPU shares have 3 decimals: exact);
    y is declared boolean (it is integral at every optimum). Reported values are divided by 1000.
    ``--cpsat-params`` sets SatParameters fields, ``name:value`` pairs (e.g. ``linearization_level:2``, which
    puts every constraint in CP-SAT's LP, for a bound closer to the MILP solvers').
  * ``cpsat-cp``: CP-SAT on the natural model written directly (n[c,j] integer, z[g,j] and y[k,j]
    booleans, n <= |c|·z, z => y, capacities as linear constraints scaled by 1000; no covers).

Every solver gets no start by default (the time to its first solution is measured); ``--start`` hands
each the seed ``allocate`` would use (``_greedy`` with the robot-level partition and local search, not
the neighbourhood step). For each, at each checkpoint: best objective, best bound, gap
(objective - bound) / objective, plus the time of the first solution, the final status and the CPU
seconds of the subprocess (CP-SAT uses both cores: its CPU is about twice its wall time). Objectives
are the model's (delay - ε per monitor kept on its unit). Times are wall-clock on a shared machine: the
load average is printed at the start and end of every instance. With ``--start`` SCIP's "first" is
its first solution better than the start, or "-".

Measured (2026-11-24, HiGHS 1.15.1, SCIP 10.0 via PySCIPOpt 6.3.0, OR-Tools 9.15.6755; 2-core machine
shared with another benchmark, load average 1.0-4.6; objective / bound after 60 s, no start):

* No solver proves optimality of any cross-robot fleet in 1 s; at 1 s every bound is the root LP's or
  nothing. Only uniform 500 x 5 is proven at all, optimum 855.84: HiGHS in 35.0 s (34.5 s CPU), SCIP
  34.7 s (31.9 s CPU), CP-SAT 20.9 s wall (31.7 s CPU on 2 workers); CP-SAT on the natural model
  (no covers) finds it but ends at bound 610.
* uniform 500 x 10: HiGHS 544 / 312, SCIP 664 / 323, CP-SAT 412 / 114, CP-SAT natural 413 / 133. Given
  300 s: HiGHS 400.3 / 329.6 (gap 18 %), SCIP 544 / 308, CP-SAT 411.1 / 142.
* uniform 1000 x 20: HiGHS no solution better than 9211 / 636.7 (root bound 635 after ~10 s); SCIP no
  bound in 60 s; CP-SAT 891.7 / 95 (allocate's seed: 1123, its 30 s run: 970); CP-SAT natural 916 / 94.
  With allocate's seed as start: HiGHS 1123 / 636.7, SCIP 1123 / 635.5, CP-SAT 1005 / 84.
* heterogeneous 500 x 5: HiGHS 936 / 636, SCIP 996 / 684 (the best bound), CP-SAT 899 / none;
  500 x 10: HiGHS 447 / 304, SCIP 858 / 302, CP-SAT 414 / none; 1000 x 20: HiGHS 15526 / 643, SCIP
  6043 / none, CP-SAT 1068 / none, CP-SAT natural 1008 / none.
* CP-SAT is the best primal heuristic here (it matches HiGHS's 900 s solution at 500 x 10 in 60 s and
  beats allocate's at 1000 x 20) but its bound, even with ``linearization_level:2``, stays far below the
  LP's: on 2 workers it hardly runs the LP. The bounds of HiGHS and SCIP are the LP relaxation's plus
  little; SCIP's moved from 304 to 323 in one run and stayed at 308 after 300 s in another (timing
  dependent). What stops all of them is the weak relaxation described in monitor_milp's docstring, not
  the solver.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks._bench import ensure_venv, loadavg  # noqa: E402

SOLVERS = ("highs", "scip", "cpsat", "cpsat-cp")
OBJ_SCALE = 1000.0  # CP-SAT objective scale (see the docstring)
GAP = 1e-4  # the relative gap every solver stops at (monitor_milp's mip_rel_gap default)
CPSAT_PARAMS = ""  # --cpsat-params, set in the child


# ===================================================================================================
# Parent: build and export the model, run the solvers, print the comparison
# ===================================================================================================


def export(m: int, n: int, uniform: bool, path: Path, start: bool) -> dict:
    """Write the covers model of one fleet (and the data of the natural CP model) to ``path``."""
    from benchmarks.milp_scaling import fleet
    from continuum.engine.verification import monitor_milp as mm

    stats = mm.MonitorStats.from_dict(fleet(m, n, seed=m + n, uniform=uniform, cross=0.1))
    cpu = mm.complete_cpu(stats)
    cl = mm._classes(stats, cpu, False)
    blocks = len(mm._blocks(cl))
    t0 = time.perf_counter()
    model = mm._build(stats, cl, 1e-3, slack=False, formulation="covers")
    build_s = time.perf_counter() - t0
    delay, tcpu = mm._topic_matrices(stats)
    cap = stats.capacity()
    arrays = {
        "c": model.c,
        "data": model.a.data,
        "indices": model.a.indices,
        "indptr": model.a.indptr,
        "shape": np.array(model.a.shape),
        "lo": model.lo,
        "hi": model.hi,
        "integrality": model.integrality,
        "ub": model.ub,
        "n_x": np.array([model.n_x]),
        "y0": np.array([model.y0]),
        "z0": np.array([model.z0]),
        # natural model
        "size": np.array([len(mb) for mb in cl.members]),
        "cpu": cl.cpu,
        "current": np.array([-1 if u is None else u for u in cl.current]),
        "group": np.array(cl.group),
        "group_topics": np.array([k for ks in cl.group_topics for k in ks]),
        "group_len": np.array([len(ks) for ks in cl.group_topics]),
        "delay": delay,
        "tcpu": tcpu,
        "cap": np.array([cap[j] for j in stats.nodes]),
    }
    seed_obj = None
    t1 = time.perf_counter()
    placement, fits = mm._greedy(stats, cl, 1e-3, partition=True)
    seed_s = time.perf_counter() - t1
    if fits:
        vec = mm._vector(model, stats, cl, placement)
        seed_obj = float(model.c @ vec)
        if start:
            arrays["start"] = vec
    np.savez(path, **arrays)
    return {
        "rows": model.a.shape[0],
        "cols": model.a.shape[1],
        "nnz": model.a.nnz,
        "int": int(model.integrality.sum()),
        "classes": len(cl.members),
        "groups": len(cl.group_topics),
        "blocks": blocks,
        "build_s": build_s,
        "seed_obj": seed_obj,
        "seed_s": seed_s,
    }


#: The peers' own environments (installed at the first run, kept): pyscipopt and ortools are not Continuum's
#: dependencies, and ortools cannot share a process with highspy anyway (see the docstring).
PEERS = {
    "scip": (Path("/tmp/continuum-bench-scip"), ["pyscipopt==6.3.0", "numpy", "scipy"], "pyscipopt"),
    "cpsat": (Path("/tmp/continuum-bench-ortools"), ["ortools==9.15.6755", "numpy", "scipy"], "ortools"),
}
PEERS["cpsat-cp"] = PEERS["cpsat"]


def peer_python(solver: str) -> str:
    """The python that runs ``solver``'s child: the shared venv's for HiGHS, the peer's own environment else
    (``sys.executable`` when it cannot be installed: the child then says the module is not importable)."""
    if solver not in PEERS:
        return sys.executable
    try:
        return str(ensure_venv(*PEERS[solver]))
    except (OSError, subprocess.CalledProcessError) as exc:
        print(f"could not install {solver}'s peer environment: {exc}", flush=True)
        return sys.executable


def run_child(solver: str, path: Path, args: argparse.Namespace) -> dict:
    cmd = [peer_python(solver), str(Path(__file__).resolve()), "--child", solver, "--model", str(path)]
    cmd += ["--checkpoints", args.checkpoints, "--workers", str(args.workers), "--cpsat-params", args.cpsat_params]
    limit = max(float(t) for t in args.checkpoints.split(","))
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=limit * 3 + 120, env=os.environ.copy())
    except subprocess.TimeoutExpired:
        return {"error": "subprocess timed out"}
    for text in reversed(done.stdout.splitlines()):
        if text.startswith("{"):
            return json.loads(text)
    return {"error": (done.stderr.strip().splitlines() or [f"exit {done.returncode}"])[-1]}


def fmt(v: float | None, width: int = 9) -> str:
    return f"{v:{width}.2f}" if v is not None and np.isfinite(v) else f"{'-':>{width}}"


def report(solver: str, out: dict, checkpoints: list[float]) -> None:
    if "skip" in out:
        print(f"  {solver:<9} skipped: {out['skip']}")
        return
    if "error" in out:
        print(f"  {solver:<9} failed: {out['error']}")
        return
    cells = []
    for t in checkpoints:
        obj, bound = at(out["trace"], t)
        gap = (obj - bound) / abs(obj) if obj is not None and bound is not None and abs(obj) > 1e-9 else None
        cells.append(f"{fmt(obj, 8)} {fmt(bound, 8)} {f'{gap:6.1%}' if gap is not None else '     -'}")
    first = out.get("first")
    print(
        f"  {solver:<9} first {fmt(first, 6)} s | "
        + " | ".join(cells)
        + f" | {out['status']:<10} solve {out['trace'][-1][0]:6.1f} s (process wall {out['wall']:6.1f} s,"
        f" cpu {out['cpu']:6.1f} s)"
    )


def at(trace: list[list[float]], t: float) -> tuple[float | None, float | None]:
    """Best objective and best bound known at time ``t`` (trace rows: time, objective, bound)."""
    obj = bound = None
    for when, o, b in trace:
        if when > t + 1e-9:
            break
        if o is not None and np.isfinite(o):
            obj = o if obj is None else min(obj, o)
        if b is not None and np.isfinite(b):
            bound = b if bound is None else max(bound, b)
    return obj, bound


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="500x5,500x10,1000x20")
    parser.add_argument("--fleets", default="uniform,heterogeneous")
    parser.add_argument("--solvers", default=",".join(SOLVERS))
    parser.add_argument("--checkpoints", default="1,10,60", help="seconds; the last is the time limit")
    parser.add_argument("--start", action="store_true", help="give every solver allocate()'s seed")
    parser.add_argument("--workers", type=int, default=2, help="CP-SAT workers")
    parser.add_argument("--cpsat-params", default="", help="extra CP-SAT SatParameters, name:value pairs")
    parser.add_argument("--child", default=None, help=argparse.SUPPRESS)
    parser.add_argument("--model", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    checkpoints = [float(t) for t in args.checkpoints.split(",")]
    if args.child:
        global CPSAT_PARAMS
        CPSAT_PARAMS = args.cpsat_params
        print(json.dumps(child(args.child, Path(args.model), checkpoints, args.workers)))
        return
    solvers = [s.strip() for s in args.solvers.split(",") if s.strip()]
    bad = [s for s in solvers if s not in SOLVERS]
    if bad:
        print(f"milp_solvers: unknown solver {bad[0]!r} (choices: {', '.join(SOLVERS)})", file=sys.stderr)
        sys.exit(2)
    print(
        f"load average at start: {loadavg()}; checkpoints {checkpoints} s; start given: {args.start}; "
        f"CP-SAT workers {args.workers}, extra parameters {args.cpsat_params!r}"
    )
    head = " | ".join(f"{f'obj@{t:g}s':>8} {f'bnd@{t:g}s':>8} {'gap':>6}" for t in checkpoints)
    with tempfile.TemporaryDirectory(prefix="milp_solvers-") as tmp:
        for kind in [f.strip() for f in args.fleets.split(",") if f.strip()]:
            for size in args.sizes.split(","):
                m, n = (int(v) for v in size.lower().split("x"))
                path = Path(tmp) / f"{kind}-{m}x{n}.npz"
                info = export(m, n, kind == "uniform", path, args.start)
                print(
                    f"\ncross-robot {kind} {m} x {n}: {info['rows']} rows, {info['cols']} cols "
                    f"({info['int']} integer), {info['nnz']} nonzeros, {info['classes']} classes, "
                    f"{info['groups']} topic sets, {info['blocks']} block(s); built in {info['build_s']:.1f} s; "
                    f"allocate's seed {fmt(info['seed_obj'], 0)} ({info['seed_s']:.1f} s); load {loadavg()}"
                )
                print(f"  {'solver':<9} {'first':>14} | {head} | status")
                for solver in solvers:
                    report(solver, run_child(solver, path, args), checkpoints)
                print(f"  load average after: {loadavg()}")


# ===================================================================================================
# Children: one solver each, in its own process; print one JSON line
# ===================================================================================================


def child(solver: str, path: Path, checkpoints: list[float], workers: int) -> dict:
    module = {"highs": "highspy", "scip": "pyscipopt", "cpsat": "ortools", "cpsat-cp": "ortools"}[solver]
    try:
        __import__(module)
    except ImportError as exc:
        return {"skip": f"{module} is not importable ({exc})"}
    d = dict(np.load(path))
    t0 = time.perf_counter()
    run = {"highs": _highs, "scip": _scip, "cpsat": _cpsat, "cpsat-cp": _cpsat_cp}[solver]
    out = run(d, checkpoints, workers)
    out["wall"] = time.perf_counter() - t0
    usage = resource.getrusage(resource.RUSAGE_SELF)
    out["cpu"] = usage.ru_utime + usage.ru_stime
    return out


def _csr(d: dict):
    from scipy.sparse import csr_matrix

    return csr_matrix((d["data"], d["indices"], d["indptr"]), shape=tuple(d["shape"]))


def _highs(d: dict, checkpoints: list[float], _workers: int) -> dict:
    import highspy

    from continuum.engine.verification.monitor_milp import HIGHS_OPTIONS

    a = _csr(d).tocsc()
    h = highspy.Highs()
    h.setOptionValue("output_flag", False)
    h.setOptionValue("time_limit", float(max(checkpoints)))
    h.setOptionValue("mip_rel_gap", GAP)
    h.setOptionValue("threads", 1)
    for name, value in HIGHS_OPTIONS.items():
        h.setOptionValue(name, value)
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = a.shape[1], a.shape[0]
    lp.col_cost_ = d["c"]
    lp.col_lower_ = np.zeros(a.shape[1])
    lp.col_upper_ = d["ub"]
    lp.row_lower_ = d["lo"]
    lp.row_upper_ = d["hi"]
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_ = a.indptr
    lp.a_matrix_.index_ = a.indices
    lp.a_matrix_.value_ = a.data
    lp.integrality_ = [
        highspy.HighsVarType.kInteger if v else highspy.HighsVarType.kContinuous for v in d["integrality"]
    ]
    h.passModel(lp)
    trace: list[list] = []
    t0 = time.perf_counter()
    first: list[float] = []

    def watch(kind, _message, out, _inp, _data) -> None:
        now = time.perf_counter() - t0
        primal = float(out.mip_primal_bound)
        dual = float(out.mip_dual_bound)
        trace.append(
            [now, primal if np.isfinite(primal) and abs(primal) < 1e50 else None, dual if np.isfinite(dual) else None]
        )
        if kind == highspy.cb.HighsCallbackType.kCallbackMipImprovingSolution and not first:
            first.append(now)

    h.setCallback(watch, None)
    h.startCallback(highspy.cb.HighsCallbackType.kCallbackMipInterrupt)
    h.startCallback(highspy.cb.HighsCallbackType.kCallbackMipImprovingSolution)
    if "start" in d:
        sol = highspy.HighsSolution()
        sol.col_value = list(d["start"])
        sol.value_valid = True
        h.setSolution(sol)
    h.run()
    now = time.perf_counter() - t0
    info = h.getInfo()
    obj = float(info.objective_function_value) if info.primal_solution_status == 2 else None
    bound = float(info.mip_dual_bound) if np.isfinite(info.mip_dual_bound) else None
    trace.append([now, obj, bound])
    status = h.modelStatusToString(h.getModelStatus())
    return {"trace": trace, "first": first[0] if first else None, "status": status, "nodes": int(info.mip_node_count)}


def _scip(d: dict, checkpoints: list[float], _workers: int) -> dict:
    import pyscipopt

    a = _csr(d)
    model = pyscipopt.Model()
    model.hideOutput()
    model.setParam("limits/gap", GAP)
    model.setParam("parallel/maxnthreads", 1)
    x = [
        model.addVar(lb=0.0, ub=float(u) if np.isfinite(u) else None, vtype="I" if integral else "C", obj=float(c))
        for c, u, integral in zip(d["c"], d["ub"], d["integrality"], strict=True)
    ]
    for r in range(a.shape[0]):
        lo, hi = d["lo"][r], d["hi"][r]
        cols, vals = a.indices[a.indptr[r] : a.indptr[r + 1]], a.data[a.indptr[r] : a.indptr[r + 1]]
        expr = pyscipopt.quicksum(float(v) * x[j] for j, v in zip(cols, vals, strict=True))
        if np.isfinite(lo) and np.isfinite(hi) and lo == hi:
            model.addCons(expr == float(lo))
        else:
            if np.isfinite(lo):
                model.addCons(expr >= float(lo))
            if np.isfinite(hi):
                model.addCons(expr <= float(hi))
    first: list[float] = []
    t0 = time.perf_counter()

    class First(pyscipopt.Eventhdlr):
        def eventinit(self):
            self.model.catchEvent(pyscipopt.SCIP_EVENTTYPE.BESTSOLFOUND, self)

        def eventexec(self, event):
            if not first:
                first.append(time.perf_counter() - t0)

    model.includeEventhdlr(First(), "first", "time of the first solution")
    if "start" in d:
        sol = model.createSol()
        for var, value in zip(x, d["start"], strict=True):
            model.setSolVal(sol, var, float(value))
        model.addSol(sol)
    trace: list[list] = []
    status = "unknown"
    for t in sorted(checkpoints):
        model.setParam("limits/time", float(t))
        model.optimize()
        now = time.perf_counter() - t0
        status = model.getStatus()
        obj = model.getPrimalbound() if model.getNSols() else None
        bound = model.getDualbound()
        trace.append([min(now, t), obj, bound if abs(bound) < 1e19 else None])
        if status != "timelimit":
            trace[-1][0] = now
            break
    return {"trace": trace, "first": first[0] if first else None, "status": status, "nodes": model.getNNodes()}


def _row_scale(vals: np.ndarray, bounds: list[float]) -> float:
    """The smallest power of 10 (<= 1e6) that makes a row's coefficients and finite bounds integral."""
    nums = np.concatenate([vals, [b for b in bounds if np.isfinite(b)]])
    for p in range(7):
        s = 10.0**p
        if np.all(np.abs(nums * s - np.rint(nums * s)) < 1e-6):
            return s
    return 1e6


class _Progress:
    """CP-SAT solution and bound callbacks -> trace rows (time, objective, bound), in model units."""

    def __init__(self, offset: float = 0.0):
        self.t0 = time.perf_counter()
        self.trace: list[list] = []
        self.first: float | None = None
        self.offset = offset

    def solution(self, obj: float) -> None:
        now = time.perf_counter() - self.t0
        if self.first is None:
            self.first = now
        self.trace.append([now, obj / OBJ_SCALE + self.offset, None])

    def bound(self, b: float) -> None:
        self.trace.append([time.perf_counter() - self.t0, None, b / OBJ_SCALE + self.offset])


def _cpsat_solve(model, checkpoints: list[float], workers: int, progress: _Progress, hint=None) -> dict:
    from ortools.sat.python import cp_model

    if hint is not None:
        for var, value in hint:
            model.add_hint(var, value)
    solver = cp_model.CpSolver()
    solver.parameters.num_workers = workers
    solver.parameters.max_time_in_seconds = float(max(checkpoints))
    solver.parameters.relative_gap_limit = GAP
    for item in CPSAT_PARAMS.replace(",", " ").split():  # name:value pairs (solver.parameters is no protobuf)
        name, value = item.split(":", 1)
        kind = type(getattr(solver.parameters, name))
        setattr(solver.parameters, name, value.lower() in ("1", "true") if kind is bool else kind(value))

    class Cb(cp_model.CpSolverSolutionCallback):
        def on_solution_callback(self) -> None:
            progress.solution(self.objective_value)

    solver.best_bound_callback = progress.bound
    progress.t0 = time.perf_counter()
    status = solver.solve(model, Cb())
    now = time.perf_counter() - progress.t0
    obj = (
        solver.objective_value / OBJ_SCALE + progress.offset
        if status in (cp_model.OPTIMAL, cp_model.FEASIBLE)
        else None
    )
    progress.trace.append([now, obj, solver.best_objective_bound / OBJ_SCALE + progress.offset])
    return {"trace": progress.trace, "first": progress.first, "status": solver.status_name(status), "nodes": 0}


def _cpsat(d: dict, checkpoints: list[float], workers: int) -> dict:
    from ortools.sat.python import cp_model

    a = _csr(d)
    model = cp_model.CpModel()
    n = a.shape[1]
    y0, z0 = int(d["y0"][0]), int(d["z0"][0])
    ub = d["ub"]
    x = []
    for j in range(n):
        top = round(ub[j]) if np.isfinite(ub[j]) else 1 << 30
        x.append(model.new_bool_var(f"v{j}") if top == 1 else model.new_int_var(0, top, f"v{j}"))
    for r in range(a.shape[0]):
        lo, hi = float(d["lo"][r]), float(d["hi"][r])
        cols, vals = a.indices[a.indptr[r] : a.indptr[r + 1]], a.data[a.indptr[r] : a.indptr[r + 1]]
        s = _row_scale(vals, [lo, hi])
        coefs = [round(v * s) for v in vals]
        low = int(np.ceil(lo * s - 1e-6)) if np.isfinite(lo) else cp_model.INT_MIN
        high = int(np.floor(hi * s + 1e-6)) if np.isfinite(hi) else cp_model.INT_MAX
        model.add_linear_constraint(sum(c * x[j] for j, c in zip(cols, coefs, strict=True)), low, high)
    c = d["c"].copy()
    c[y0:z0] -= 1e-6  # drop the tiny reception cost: the objective is then exact in integers
    coef = np.rint(c * OBJ_SCALE).astype(int)
    model.minimize(sum(int(k) * x[j] for j, k in enumerate(coef) if k))
    hint = list(zip(x, (round(v) for v in d["start"]), strict=True)) if "start" in d else None
    return _cpsat_solve(model, checkpoints, workers, _Progress(), hint)


def _cpsat_cp(d: dict, checkpoints: list[float], workers: int) -> dict:
    from ortools.sat.python import cp_model

    model = cp_model.CpModel()
    size, cpu, current, group = d["size"], d["cpu"], d["current"], d["group"]
    delay, tcpu, cap = d["delay"], d["tcpu"], d["cap"]
    sets, at_ = [], 0
    for length in d["group_len"]:
        sets.append([int(k) for k in d["group_topics"][at_ : at_ + length]])
        at_ += length
    n_c, n_j = cpu.shape
    n_k = delay.shape[0]
    count = [[model.new_int_var(0, int(size[c]), f"n{c}_{j}") for j in range(n_j)] for c in range(n_c)]
    z = [[model.new_bool_var(f"z{g}_{j}") for j in range(n_j)] for g in range(len(sets))]
    read = sorted({k for ks in sets for k in ks})
    y = {(k, j): model.new_bool_var(f"y{k}_{j}") for k in read for j in range(n_j)}
    for c in range(n_c):
        model.add(sum(count[c]) == int(size[c]))
        for j in range(n_j):
            model.add(count[c][j] <= int(size[c]) * z[group[c]][j])
    for g, ks in enumerate(sets):
        for j in range(n_j):
            for k in ks:
                model.add_implication(z[g][j], y[(k, j)])
    for j in range(n_j):
        terms = [round(cpu[c, j] * 1000) * count[c][j] for c in range(n_c)]
        terms += [round(tcpu[k, j] * 1000) * y[(k, j)] for k in read]
        model.add(sum(terms) <= int(np.floor(cap[j] * 1000 + 1e-6)))
    objective = [round(delay[k, j] * OBJ_SCALE) * y[(k, j)] for k in read for j in range(n_j)]
    objective += [-round(1e-3 * OBJ_SCALE) * count[c][int(current[c])] for c in range(n_c) if current[c] >= 0]
    model.minimize(sum(objective))
    assert n_k >= len(read)
    hint = None
    if "start" in d:
        s = d["start"]
        y0, z0 = int(d["y0"][0]), int(d["z0"][0])
        hint = [(count[c][j], round(s[c * n_j + j])) for c in range(n_c) for j in range(n_j)]
        hint += [(z[g][j], round(s[z0 + g * n_j + j])) for g in range(len(sets)) for j in range(n_j)]
        hint += [(y[(k, j)], round(s[y0 + k * n_j + j])) for k in read for j in range(n_j)]
    return _cpsat_solve(model, checkpoints, workers, _Progress(), hint)


if __name__ == "__main__":
    main()
