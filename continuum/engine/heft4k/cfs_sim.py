"""Discrete-event simulation of DAG containers on multi-core nodes under Linux CFS (spec 02 section 10).

What Kubernetes does with a DAG when nobody synchronises it (thesis 3.3.2, "condition 1" lost): every pod is
deployed at once and waits on its subscriptions; a task becomes runnable when all its inputs have arrived
(publish/subscribe, "condition 2" kept); the kernel of each node shares that node's CPUs among the runnable
tasks by their nice weights. Default Kubernetes, HEFT on Kubernetes and HEFT4K differ only in the mapping and
the niceness they feed in (:mod:`continuum.engine.heft4k.k8s_baselines`).

Model (the spec's proposal, parameters where it leaves a choice):

- Transfers start when the producer finishes and take ``platform.comm_time`` (routed path, no contention);
  on the same node they take 0. A task is runnable from the moment its last input arrives.
- CPU sharing is the fluid limit of CFS with the kernel's ``sched_prio_to_weight`` table: a node with k
  CPUs gives runnable task i the rate ``min(1, k * w_i / sum w)``, capped shares being water-filled to the
  others (a task uses at most one CPU). It is what CFS converges to over a few scheduling periods; slices,
  wake-up preemption and per-CPU run queues are not modelled. A task of cost c on its node finishes after
  c time units at rate 1.
- A *preemption* is counted each time a running task's rate drops (a task with a higher share arrived).
  With ``ranks``: *priority-inversion time* is the node time during which a task is slowed down while a
  lower-ranked task runs on the same node, and *priority-inversion CPU* the CPU time those lower-ranked
  tasks get meanwhile.

The result is a :class:`Schedule` like any plan, so predicted and executed Gantt charts can be drawn side by
side: one assignment per task on its node with ``start`` = when it became runnable, ``finish`` = when it
completed, and its niceness. ``metrics`` holds the figures above, per-node busy time, inter-node traffic, the
transfers (for red boxes) and, with ``trace=True``, each task's piecewise-constant CPU rate (``segments``).
"""

from __future__ import annotations

import heapq
from collections.abc import Mapping
from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment, Schedule

__all__ = ["NICE_WEIGHTS", "cpu_rates", "nice_weight", "simulate"]

#: Linux ``sched_prio_to_weight`` (kernel/sched/core.c): CFS load weight of nice -20 ... 19; nice 0 is 1024.
NICE_WEIGHTS: tuple[int, ...] = (
    88761, 71755, 56483, 46273, 36291,
    29154, 23254, 18705, 14949, 11916,
    9548, 7620, 6100, 4904, 3906,
    3121, 2501, 1991, 1586, 1277,
    1024, 820, 655, 526, 423,
    335, 272, 215, 172, 137,
    110, 87, 70, 56, 45,
    36, 29, 23, 18, 15,
)  # fmt: skip

_EPS = 1e-9


def nice_weight(nice: int) -> int:
    """CFS weight of a niceness (clamped to [-20, 19] like ``setpriority``)."""
    return NICE_WEIGHTS[min(19, max(-20, int(nice))) + 20]


def cpu_rates(weights: list[float], cores: int) -> list[float]:
    """Fluid CFS: each runnable task's share of ``cores`` CPUs, proportional to weight, at most 1 each."""
    n = len(weights)
    if n <= cores:
        return [1.0] * n
    rates = [0.0] * n
    left_cpus, left_weight = float(cores), float(sum(weights))
    order = sorted(range(n), key=lambda i: -weights[i])
    k = 0
    while k < n and left_cpus * weights[order[k]] >= left_weight:  # would get more than one CPU: cap it
        rates[order[k]] = 1.0
        left_cpus -= 1.0
        left_weight -= weights[order[k]]
        k += 1
    for i in order[k:]:
        rates[i] = left_cpus * weights[i] / left_weight
    return rates


class _Node:
    __slots__ = ("active", "busy", "cores", "inversion", "inversion_cpu", "inverted", "last", "rate", "version")

    def __init__(self, cores: int):
        self.cores = cores
        self.active: dict[str, float] = {}  # task -> remaining work (time at rate 1)
        self.rate: dict[str, float] = {}
        self.last = 0.0
        self.version = 0
        self.busy = 0.0
        self.inverted = 0.0  # CPU share going to tasks ranked below a slowed-down task (0: no inversion)
        self.inversion = 0.0
        self.inversion_cpu = 0.0


def simulate(
    dag: TaskGraph,
    platform: Platform,
    placement: Mapping[str, str],
    niceness: Mapping[str, int] | None = None,
    *,
    ranks: Mapping[str, float] | None = None,
    algorithm: str = "simulated",
    trace: bool = True,
) -> Schedule:
    """Run ``dag`` with each task on node ``placement[task]`` at ``niceness[task]`` (default 0)."""
    niceness = niceness or {}
    cost = _costs(dag, platform, placement)
    weight = {t: nice_weight(niceness.get(t, 0)) for t in dag.tasks}
    nodes = {p.id: _Node(p.cores) for p in platform.processors}
    pred, succ = dag.predecessors(), dag.successors()
    missing = {t: len(pred[t]) for t in dag.tasks}
    start: dict[str, float] = {}
    finish: dict[str, float] = {}
    segments: dict[str, list[list[float | None]]] = {t: [] for t in dag.tasks} if trace else {}
    transfers: list[dict[str, Any]] = []
    stats = {"preemptions": 0, "traffic": 0.0}
    heap: list[tuple[float, int, int, str]] = []  # (time, seq, kind, key); kind 0 = input arrives, 1 = node
    seq = 0

    def push(time: float, kind: int, key: str) -> None:
        nonlocal seq
        seq += 1
        heapq.heappush(heap, (time, seq, kind, key))

    def advance(node: _Node, now: float) -> None:
        dt = now - node.last
        if dt > 0:
            for t, r in node.rate.items():
                node.active[t] -= r * dt
                node.busy += r * dt
            if node.inverted:
                node.inversion += dt
                node.inversion_cpu += node.inverted * dt
        node.last = now

    def reshare(name: str, node: _Node, now: float) -> None:
        tasks = list(node.active)
        rates = cpu_rates([weight[t] for t in tasks], node.cores)
        new = dict(zip(tasks, rates, strict=True))
        for t, r in new.items():
            old = node.rate.get(t)
            if old is not None and r < old - 1e-12:
                stats["preemptions"] += 1
            if trace and (old is None or abs(r - old) > 1e-12):
                seg = segments[t]
                if seg and seg[-1][1] is None:
                    seg[-1][1] = now
                seg.append([now, None, r])
        node.rate = new
        node.inverted = _inverted(new, ranks) if ranks else 0.0
        node.version += 1
        if new:
            when = min(node.active[t] / r for t, r in new.items())
            push(now + max(0.0, when), 1, f"{node.version}|{name}")

    for t in dag.tasks:
        if missing[t] == 0:
            push(0.0, 0, t)
    while heap:
        now = heap[0][0]
        touched: dict[str, _Node] = {}
        while heap and heap[0][0] <= now + _EPS * max(1.0, now):
            _, _, kind, key = heapq.heappop(heap)
            if kind == 0:  # every input of task ``key`` has arrived: it becomes runnable
                name = placement[key]
                node = nodes[name]
                advance(node, now)
                node.active[key] = cost[key]
                start[key] = now
                touched[name] = node
                continue
            version, name = key.split("|", 1)
            node = nodes[name]
            if int(version) != node.version:
                continue  # superseded by a later reshare
            advance(node, now)
            touched[name] = node
            for t in [t for t, left in node.active.items() if left <= _EPS * max(1.0, cost[t])]:
                del node.active[t]
                del node.rate[t]
                finish[t] = now
                if trace and segments[t] and segments[t][-1][1] is None:
                    segments[t][-1][1] = now
                for e in succ[t]:
                    src, dst = placement[t], placement[e.dst]
                    arrival = now + (platform.comm_time(src, dst, e.data) if src != dst else 0.0)
                    if src != dst:
                        stats["traffic"] += e.data
                        transfers.append(
                            {"src": t, "dst": e.dst, "from": src, "to": dst, "start": now, "finish": arrival}
                        )
                    missing[e.dst] -= 1
                    if missing[e.dst] == 0:
                        push(max(arrival, _ready(e.dst, pred, finish, placement, platform)), 0, e.dst)
        for name, node in touched.items():
            reshare(name, node, now)

    if len(finish) != len(dag.tasks):  # cannot happen for a valid DAG; a guard against silent loss
        raise RuntimeError(f"simulation ended with {len(dag.tasks) - len(finish)} tasks unfinished")
    assignments = [
        Assignment(t, placement[t], start[t], finish[t], niceness=niceness.get(t, 0))
        for t in sorted(dag.tasks, key=lambda t: (start[t], finish[t]))
    ]
    metrics: dict[str, Any] = {
        "preemptions": stats["preemptions"],
        "busy": {name: node.busy for name, node in nodes.items()},
        "traffic_mbit": stats["traffic"],
        "transfers": transfers,
    }
    if ranks:
        metrics["priority_inversion_time"] = sum(node.inversion for node in nodes.values())
        metrics["priority_inversion_cpu"] = sum(node.inversion_cpu for node in nodes.values())
    if trace:
        metrics["segments"] = segments
    return Schedule(algorithm, assignments, ranks=dict(ranks or {}), params={"simulator": "cfs-fluid"}, metrics=metrics)


def _ready(task: str, pred, finish, placement, platform: Platform) -> float:
    """When the last input of ``task`` arrives (all its producers have finished)."""
    ready = 0.0
    for e in pred[task]:
        src, dst = placement[e.src], placement[task]
        arrival = finish[e.src] + (platform.comm_time(src, dst, e.data) if src != dst else 0.0)
        ready = max(ready, arrival)
    return ready


def _inverted(rates: Mapping[str, float], ranks: Mapping[str, float]) -> float:
    """CPU share given to tasks ranked strictly below some task that gets less than a whole CPU."""
    slowed = [ranks.get(t, 0.0) for t, r in rates.items() if r < 1.0 - 1e-12]
    if not slowed:
        return 0.0
    top = max(slowed)
    return sum(r for t, r in rates.items() if ranks.get(t, 0.0) < top - 1e-9)


def _costs(dag: TaskGraph, platform: Platform, placement: Mapping[str, str]) -> dict[str, float]:
    cost: dict[str, float] = {}
    for tid, task in dag.tasks.items():
        node = placement.get(tid)
        if node is None:
            raise InputError(f"task {tid!r} is not placed on any node", "placement")
        if node not in platform.index:
            raise InputError(f"task {tid!r} is placed on unknown node {node!r}", "placement")
        c = platform.cost(task, platform.processors[platform.index[node]])
        if c is None:
            raise InputError(f"task {tid!r} cannot run on node {node!r}", "placement")
        cost[tid] = c
    return cost
