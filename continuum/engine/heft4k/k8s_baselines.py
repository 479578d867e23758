"""The schedulers HEFT4K is compared with in thesis 3.3.2 / 4.3.2, run in the same CFS simulator.

- ``k8s-default``: the default kube-scheduler as spec 02 section 9.1 models it. DAG-blind: pods are created
  in topological order (input order among ready tasks) and each goes to the feasible node with the best
  score, ties broken uniformly at random (seeded), as kube-scheduler's ``selectHost`` does. Filter
  (NodeResourcesFit): the node's pod count stays under its share of ``pod_capacity`` (default 160 pods on
  12 CPUs, i.e. 160/12 per CPU, spread over the nodes as evenly as the cores allow, so 27,27,27,27,26,26
  on the thesis' 6 x 2 CPUs) and the CPU/memory requests fit. Score: LeastAllocated + BalancedAllocation,
  both 0-100 in integers like the kube-scheduler plugins. Every task runs at nice 0. A DAG with more tasks
  than the cluster takes raises :class:`Unschedulable` (the thesis: Kubernetes fails above 160 tasks).
- ``heft-k8s``: the HEFT (look-ahead) mapping, every task nice 0, no start times.
- ``heft4k``: the same mapping with the Eq. 3.16 niceness.
- ``heft-ideal``: the HEFT plan itself (global synchronisation, no preemption): the lower reference.
- ``dpe``: spec 02 section 9.3's model of DPE (Zhao et al., INFOCOM 2021, the thesis' ref. [96]), executed
  as a static plan: see :func:`dpe`.

The first three are executed by :func:`continuum.engine.heft4k.cfs_sim.simulate`; all return a :class:`Schedule`.
"""

from __future__ import annotations

import math
import random
from collections.abc import Mapping
from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment, Schedule
from continuum.engine.heft4k.cfs_sim import simulate
from continuum.engine.heft4k.heft4k import heft4k

__all__ = [
    "PODS_PER_CPU",
    "SCHEDULERS",
    "Unschedulable",
    "compare",
    "dpe",
    "k8s_default_placement",
    "pod_capacities",
    "run_heft4k",
    "run_heft_k8s",
    "run_k8s_default",
    "speedup",
]

#: Pods per CPU of the default-Kubernetes model: 160 pods on the thesis' 6 nodes x 2 CPUs.
PODS_PER_CPU = 160 / 12
SCHEDULERS = ("k8s-default", "heft-k8s", "heft4k", "heft-ideal", "dpe")


class Unschedulable(InputError):
    """The default-Kubernetes model found no node for a pod (the cluster is full)."""

    def __init__(self, message: str, pending: list[str]):
        super().__init__(message, "tasks")
        self.pending = pending


def speedup(baseline: float, other: float) -> float:
    """Spec 02 section 0: speedup % of ``other`` over ``baseline`` = (M_baseline / M_other - 1) * 100."""
    if other <= 0:
        raise InputError(f"makespan must be positive, not {other!r}", "makespan")
    return (baseline / other - 1.0) * 100.0


# ---- default Kubernetes ----------------------------------------------------------------------------
def pod_capacities(platform: Platform, pod_capacity: int | None = None) -> dict[str, int]:
    """Max pods per node: ``pod_capacity`` spread over the nodes in proportion to their cores.

    Largest remainders first, ties to the earlier node: 160 on 6 x 2 CPUs gives 27,27,27,27,26,26.
    """
    cores = [p.cores for p in platform.processors]
    total = round(PODS_PER_CPU * sum(cores)) if pod_capacity is None else pod_capacity
    if isinstance(total, bool) or not isinstance(total, int) or total < 0:
        raise InputError(f"pod_capacity must be a non-negative integer, not {pod_capacity!r}", "pod_capacity")
    exact = [total * c / sum(cores) for c in cores]
    caps = [math.floor(x) for x in exact]
    by_remainder = sorted(range(len(cores)), key=lambda i: (-(exact[i] - caps[i]), i))
    for i in by_remainder[: total - sum(caps)]:
        caps[i] += 1
    return {p.id: caps[i] for i, p in enumerate(platform.processors)}


def k8s_default_placement(
    dag: TaskGraph,
    platform: Platform,
    *,
    seed: int = 0,
    pod_capacity: int | None = None,
    pod_cpu_m: int | None = None,
    memory_mib: Mapping[str, int] | None = None,
    pod_memory_mib: int | None = None,
) -> dict[str, str]:
    """Task -> node as the default kube-scheduler would bind the DAG's pods (module docstring).

    Requests default to what fills the cluster exactly at its pod capacity (CPU in millicores; memory
    proportional to cores when ``memory_mib`` per node is not given), so the pod count is what binds.
    Raises :class:`Unschedulable` naming the first pod no node can take.
    """
    rng = random.Random(seed)
    caps = pod_capacities(platform, pod_capacity)
    cpu_alloc = {p.id: 1000 * p.cores for p in platform.processors}
    mem_alloc = dict(memory_mib) if memory_mib else {p.id: 1024 * p.cores for p in platform.processors}
    missing = [p.id for p in platform.processors if p.id not in mem_alloc]
    if missing:
        raise InputError(f"no memory given for node {missing[0]!r}", "memory_mib")
    busy = [p.id for p in platform.processors if caps[p.id] > 0]
    if pod_cpu_m is None:
        pod_cpu_m = min((cpu_alloc[n] // caps[n] for n in busy), default=1000)
    if pod_memory_mib is None:
        pod_memory_mib = min((mem_alloc[n] // caps[n] for n in busy), default=1)
    req_cpu = dict.fromkeys(cpu_alloc, 0)
    req_mem = dict.fromkeys(cpu_alloc, 0)
    pods = dict.fromkeys(cpu_alloc, 0)
    placement: dict[str, str] = {}
    order = dag.topological_order()
    for i, tid in enumerate(order):
        task = dag.tasks[tid]
        best: list[str] = []
        best_score = -1
        for proc in platform.processors:
            n = proc.id
            if platform.cost(task, proc) is None:
                continue  # no image for this node (arch/class): filtered like a node selector
            cpu, mem = req_cpu[n] + pod_cpu_m, req_mem[n] + pod_memory_mib
            if pods[n] + 1 > caps[n] or cpu > cpu_alloc[n] or mem > mem_alloc[n]:
                continue
            score = _least_allocated(cpu, cpu_alloc[n], mem, mem_alloc[n]) + _balanced(
                cpu, cpu_alloc[n], mem, mem_alloc[n]
            )
            if score > best_score:
                best, best_score = [n], score
            elif score == best_score:
                best.append(n)
        if not best:
            pending = order[i:]
            raise Unschedulable(
                f"k8s-default: pod {tid!r} fits no node (cluster pod capacity {sum(caps.values())}, "
                f"{len(pending)} pods pending)",
                pending,
            )
        node = rng.choice(best)
        placement[tid] = node
        req_cpu[node] += pod_cpu_m
        req_mem[node] += pod_memory_mib
        pods[node] += 1
    return placement


def _least_allocated(cpu: int, cpu_alloc: int, mem: int, mem_alloc: int) -> int:
    """kube-scheduler NodeResourcesFit, LeastAllocated strategy, CPU and memory weighted 1:1."""
    return ((cpu_alloc - cpu) * 100 // cpu_alloc + (mem_alloc - mem) * 100 // mem_alloc) // 2


def _balanced(cpu: int, cpu_alloc: int, mem: int, mem_alloc: int) -> int:
    """kube-scheduler NodeResourcesBalancedAllocation: 100 * (1 - std of the requested fractions)."""
    fc, fm = min(1.0, cpu / cpu_alloc), min(1.0, mem / mem_alloc)
    return int((1.0 - abs(fc - fm) / 2.0) * 100)


# ---- the schedulers --------------------------------------------------------------------------------
def run_k8s_default(dag: TaskGraph, platform: Platform, *, seed: int = 0, trace: bool = False, **kw: Any) -> Schedule:
    placement = k8s_default_placement(dag, platform, seed=seed, **kw)
    return simulate(dag, platform, placement, None, algorithm="k8s-default", trace=trace)


def run_heft_k8s(dag: TaskGraph, platform: Platform, plan: Schedule | None = None, *, trace: bool = False) -> Schedule:
    plan = plan or heft4k(dag, platform)
    placement = {a.task: a.processor for a in plan.assignments}
    return simulate(dag, platform, placement, None, ranks=plan.ranks, algorithm="heft-k8s", trace=trace)


def run_heft4k(dag: TaskGraph, platform: Platform, plan: Schedule | None = None, *, trace: bool = False) -> Schedule:
    plan = plan or heft4k(dag, platform)
    placement = {a.task: a.processor for a in plan.assignments}
    nice = {a.task: a.niceness or 0 for a in plan.assignments}
    return simulate(dag, platform, placement, nice, ranks=plan.ranks, algorithm="heft4k", trace=trace)


def compare(
    dag: TaskGraph, platform: Platform, *, seed: int = 0, trace: bool = False, **heft4k_params: Any
) -> dict[str, Schedule | None]:
    """Every scheduler of :data:`SCHEDULERS` on one DAG; ``k8s-default`` is ``None`` when unschedulable."""
    plan = heft4k(dag, platform, **heft4k_params)
    try:
        k8s: Schedule | None = run_k8s_default(dag, platform, seed=seed, trace=trace)
    except Unschedulable:
        k8s = None
    return {
        "k8s-default": k8s,
        "heft-k8s": run_heft_k8s(dag, platform, plan, trace=trace),
        "heft4k": run_heft4k(dag, platform, plan, trace=trace),
        "heft-ideal": plan,
        "dpe": dpe(dag, platform),
    }


# ---- DPE -----------------------------------------------------------------------------------------
def dpe(dag: TaskGraph, platform: Platform) -> Schedule:
    """DPE as spec 02 section 9.3 models it: a forward dynamic programme over the DAG, static plan.

    Servers are the individual CPUs (transfers inside a node free). Tasks are taken in topological order;
    for task f and CPU s, ``T[f][s]`` = its finish time on s given its (already fixed) predecessors and
    s's availability. A task's CPU is fixed when its first successor is evaluated, to the CPU m minimising
    ``min_s (T[p][m] + comm(m -> s) + t(f, s))`` for that successor f (the DP's min over m), and its slot is
    reserved then; exit tasks take ``argmin_s T[f][s]`` at the end. Ties go to the lower CPU index. One
    route per pair (no stream splitting); no insertion.
    """
    table = platform.cost_table(dag)
    lat, inv = platform.comm_matrices()
    cpus = [(n, c) for n, p in enumerate(platform.processors) for c in range(p.cores)]
    avail = [0.0] * len(cpus)
    pred, succ = dag.predecessors(), dag.successors()
    cost_on = {tid: dict(row) for tid, row in table.items()}
    fixed: dict[str, tuple[int, float, float]] = {}  # task -> (cpu, start, finish)

    def comm(n: int, m: int, data: float) -> float:
        return 0.0 if n == m else lat[n][m] + data * inv[n][m]

    def ready_on(tid: str, n: int) -> float:
        r = 0.0
        for e in pred[tid]:
            c, _, f = fixed[e.src]
            r = max(r, f + comm(cpus[c][0], n, e.data))
        return r

    def finish_on(tid: str, s: int) -> float:
        n = cpus[s][0]
        return max(ready_on(tid, n), avail[s]) + cost_on[tid][n]

    def fix(tid: str, s: int) -> None:
        f = finish_on(tid, s)
        fixed[tid] = (s, f - cost_on[tid][cpus[s][0]], f)
        avail[s] = f

    def candidates(tid: str) -> list[int]:
        return [s for s, (n, _) in enumerate(cpus) if n in cost_on[tid]]

    for tid in dag.topological_order():
        for e in pred[tid]:  # tid is the first successor evaluated for any unfixed predecessor
            p = e.src
            if p in fixed:
                continue
            best_m, best_v = -1, math.inf
            for m in candidates(p):
                t_pm = finish_on(p, m)
                v = min(t_pm + comm(cpus[m][0], cpus[s][0], e.data) + cost_on[tid][cpus[s][0]] for s in candidates(tid))
                if v < best_v - 1e-12:
                    best_m, best_v = m, v
            fix(p, best_m)
    for tid in dag.topological_order():
        if not succ[tid] and tid not in fixed:
            fix(tid, min(candidates(tid), key=lambda s: (finish_on(tid, s), s)))
    names = [p.id for p in platform.processors]
    assignments = [
        Assignment(t, names[cpus[c][0]], s, f, core=cpus[c][1])
        for t, (c, s, f) in sorted(fixed.items(), key=lambda kv: (kv[1][1], kv[0]))
    ]
    return Schedule("dpe", assignments, params={"model": "spec 02 section 9.3"})
