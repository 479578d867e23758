"""HEFT4K: HEFT mapping + task niceness for Kubernetes (thesis 3.3.2, Eq. 3.16, Figs. 3.29-3.30).

The cluster is the graph G^c of :func:`continuum.engine.core.cluster.cluster_platform`: one processor per node,
``cores`` CPUs each, routed links. HEFT4K keeps only two things of a HEFT plan, because Kubernetes cannot
impose start times (no global synchronisation): the task-to-node mapping (each pod pinned to its HEFT node)
and the HEFT rank, turned into an OS niceness so that the kernel runs higher-ranked tasks first:

    niceness(v) = (nice_H - nice_L) * HEFT_R(v) / max_u HEFT_R(u) + nice_L                   (Eq. 3.16)

Readings of the thesis (spec 02 sections 6-7), each a parameter with the spec's reading as default:

- HEFT_R is the upward rank of Eq. 2.1 on the node-level cluster: mean cost over the nodes that can run the
  task, mean transfer time over ordered pairs of distinct nodes (``rank_mode="mean"``).
- Processors are the individual CPUs; transfers between CPUs of one node are free; insertion policy.
- ``lookahead=True`` (the thesis uses the look-ahead HEFT of Bittencourt et al., its ref. [94]): for each
  candidate CPU p of task t, t is placed on p tentatively, then t's children are placed one after the other
  in rank order with plain EFT (parents not yet placed are ignored; a child goes at the end of a CPU's
  queue, no insertion, in this estimate); p minimises the latest of those children's finish times (t's own
  finish when it has no children). Ties: the smaller own finish, then the lower node/CPU index.
  ``lookahead=False`` is plain HEFT, the rules of :mod:`continuum.engine.device.heft` (identical schedules on
  single-core platforms).
- nice_H is the *high-priority* end (the top-ranked task gets it), so ``nice_high <= nice_low``; defaults
  0 and 19 need no privilege; negative values need CAP_SYS_NICE (:func:`nice_container`). Rounding
  ``floor(x + 0.5)``, clamped to the Linux range [-20, 19].
- The max in Eq. 3.16 runs over the whole DAG (the formula), not per device (the prose).

The result is a :class:`Schedule` (algorithm ``"heft4k"``) whose assignments name the node, the CPU
(``core``) and the ``niceness``; its start/finish times are the ideal, synchronised HEFT plan.
"""

from __future__ import annotations

import heapq
import math
from bisect import bisect_right
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment, Schedule
from continuum.engine.device.heft import earliest_slot, upward_ranks
from continuum.engine.device.registry import register

__all__ = [
    "NICE_MAX",
    "NICE_MIN",
    "NUMPY_MIN_WORK",
    "ROUNDINGS",
    "heft4k",
    "map_dag",
    "nice_container",
    "niceness",
    "placements",
    "with_niceness",
]

NICE_MIN, NICE_MAX = -20, 19
ROUNDINGS = ("half-up", "floor", "ceil")


# ---- Eq. 3.16 ---------------------------------------------------------------------------------------
def niceness(
    ranks: Mapping[str, float], nice_high: int = 0, nice_low: int = 19, rounding: str = "half-up"
) -> dict[str, int]:
    """Eq. 3.16: the niceness of every task from its HEFT rank (the top-ranked task gets ``nice_high``)."""
    for name, value in (("nice_high", nice_high), ("nice_low", nice_low)):
        if isinstance(value, bool) or not isinstance(value, int) or not NICE_MIN <= value <= NICE_MAX:
            raise InputError(f"{name} must be an integer in [{NICE_MIN}, {NICE_MAX}], not {value!r}", name)
    if nice_high > nice_low:
        raise InputError(
            f"nice_high ({nice_high}) is the high-priority end and must not exceed nice_low ({nice_low})",
            "nice_high",
        )
    if rounding not in ROUNDINGS:
        raise InputError(f"unknown rounding {rounding!r} (choose from {', '.join(ROUNDINGS)})", "rounding")
    top = max(ranks.values(), default=0.0)
    out: dict[str, int] = {}
    for tid, rank in ranks.items():
        x = nice_high if top <= 0 else (nice_high - nice_low) * rank / top + nice_low
        x = round(x, 9)  # float noise must not flip a tie such as 8.5
        n = math.floor(x + 0.5) if rounding == "half-up" else math.floor(x) if rounding == "floor" else math.ceil(x)
        out[tid] = min(NICE_MAX, max(NICE_MIN, n))
    return out


# ---- HEFT on multi-core nodes ----------------------------------------------------------------------
class _Cluster:
    """CPU timelines of a node-level platform (index ``c`` over all CPUs; ``node_of[c]``, ``cpus[n]``)."""

    def __init__(self, platform: Platform):
        self.names = [p.id for p in platform.processors]
        self.cpus: list[list[int]] = []
        self.node_of: list[int] = []
        self.core_of: list[int] = []
        for n, proc in enumerate(platform.processors):
            self.cpus.append(list(range(len(self.node_of), len(self.node_of) + proc.cores)))
            self.node_of += [n] * proc.cores
            self.core_of += list(range(proc.cores))
        self.starts: list[list[float]] = [[] for _ in self.node_of]
        self.finishes: list[list[float]] = [[] for _ in self.node_of]
        self.last = [0.0] * len(self.node_of)  # latest finish on each CPU (end of its queue)

    def reserve(self, c: int, start: float, finish: float) -> None:
        at = bisect_right(self.finishes[c], start)
        self.starts[c].insert(at, start)
        self.finishes[c].insert(at, finish)
        if finish > self.last[c]:
            self.last[c] = finish


def map_dag(
    dag: TaskGraph,
    platform: Platform,
    *,
    lookahead: bool = True,
    rank_mode: str = "mean",
    insertion: bool = True,
    ranks: Mapping[str, float] | None = None,
    allowed: Mapping[str, Iterable[str]] | None = None,
    algorithm: str = "heft4k",
) -> Schedule:
    """The HEFT plan of ``dag`` on the CPUs of ``platform`` (no niceness yet).

    ``ranks`` replaces the upward ranks as the priority (Algorithm 2 keeps the original ones);
    ``allowed`` restricts tasks to some nodes (Algorithm 2 locks unaffected tasks to their node this way,
    which is what its 9999999 costs achieve without distorting any mean).
    """
    table = _cost_table(dag, platform, allowed or {})
    if ranks is None:
        ranks = upward_ranks(dag, platform, rank_mode, platform.cost_table(dag))
    else:
        missing = [t for t in dag.tasks if t not in ranks]
        if missing:
            raise InputError(f"no rank for task {missing[0]!r}", "ranks")
    lat, inv = platform.comm_matrices()
    cl = _Cluster(platform)
    pred, succ = dag.predecessors(), dag.successors()
    position = {tid: i for i, tid in enumerate(dag.tasks)}
    key = {t: (-round(r, 9), position[t]) for t, r in ranks.items()}
    # Children in rank order, for the look-ahead.
    kids = {t: sorted(succ[t], key=lambda e: key[e.dst]) for t in dag.tasks}
    waiting = {tid: len(pred[tid]) for tid in dag.tasks}
    heap = [(key[t], t) for t, n in waiting.items() if n == 0]
    heapq.heapify(heap)
    where: dict[str, int] = {}  # task -> CPU
    start: dict[str, float] = {}
    finish: dict[str, float] = {}
    order: list[str] = []
    vec: _Vectors | None = None

    while heap:
        _, tid = heapq.heappop(heap)
        inputs = [(finish[e.src], cl.node_of[where[e.src]], e.data) for e in pred[tid]]
        options = []  # (own finish, cpu, start)
        for n, w in table[tid]:
            ready = 0.0
            for aft, q, data in inputs:
                arrival = aft + lat[q][n] + data * inv[q][n]
                if arrival > ready:
                    ready = arrival
            for c in cl.cpus[n]:
                s = earliest_slot(cl.starts[c], cl.finishes[c], ready, w) if insertion else max(ready, cl.last[c])
                options.append((s + w, c, s))
        if lookahead and kids[tid] and len(options) > 1:
            work = len(options) * sum(len(table[e.dst]) for e in kids[tid])
            if work >= NUMPY_MIN_WORK:
                vec = vec or _Vectors(cl, lat, inv)
                worst = _lookahead_np(tid, options, kids[tid], table, pred, where, finish, cl, vec)
            else:
                worst = [_lookahead(tid, o, kids[tid], table, pred, where, finish, cl, lat, inv) for o in options]
            best = min(zip(worst, options, strict=True), key=lambda wo: (wo[0], wo[1][0], wo[1][1]))[1]
        else:
            best = min(options, key=lambda o: (o[0], o[1]))
        f, c, s = best
        cl.reserve(c, s, f)
        where[tid], start[tid], finish[tid] = c, s, f
        order.append(tid)
        for e in succ[tid]:
            waiting[e.dst] -= 1
            if waiting[e.dst] == 0:
                heapq.heappush(heap, (key[e.dst], e.dst))

    assignments = [
        Assignment(tid, cl.names[cl.node_of[where[tid]]], start[tid], finish[tid], core=cl.core_of[where[tid]])
        for tid in order
    ]
    return Schedule(
        algorithm,
        assignments,
        ranks=dict(ranks),
        params={"lookahead": lookahead, "rank_mode": rank_mode, "insertion": insertion},
    )


#: Look-ahead evaluations (candidate CPUs x children's candidate nodes) from which numpy is faster.
NUMPY_MIN_WORK = 256


def _lookahead(tid, option, children, table, pred, where, finish, cl, lat, inv) -> float:
    """Latest finish of ``tid``'s children placed by plain EFT after ``tid`` tentatively takes ``option``."""
    f_t, c_t, _ = option
    tent_node = {tid: cl.node_of[c_t]}
    tent_finish = {tid: f_t}
    last = {c_t: max(cl.last[c_t], f_t)}  # queue ends changed by the tentative placements
    worst = f_t
    for e in children:
        child = e.dst
        known = []
        for pe in pred[child]:
            if pe.src in tent_node:
                known.append((tent_finish[pe.src], tent_node[pe.src], pe.data))
            elif pe.src in where:
                known.append((finish[pe.src], cl.node_of[where[pe.src]], pe.data))
        best_f, best_c = math.inf, -1
        for n, w in table[child]:
            ready = 0.0
            for aft, q, data in known:
                arrival = aft + lat[q][n] + data * inv[q][n]
                if arrival > ready:
                    ready = arrival
            for c in cl.cpus[n]:
                f = max(ready, last.get(c, cl.last[c])) + w
                if f < best_f:
                    best_f, best_c = f, c
        tent_node[child], tent_finish[child] = cl.node_of[best_c], best_f
        last[best_c] = best_f
        if best_f > worst:
            worst = best_f
    return worst


class _Vectors:
    """numpy copies of the cluster for the vectorised look-ahead (large clusters)."""

    def __init__(self, cl: _Cluster, lat: list[list[float]], inv: list[list[float]]):
        import numpy as np

        self.np = np
        self.lat = np.array(lat, dtype=float)
        self.inv = np.array(inv, dtype=float)
        self.node_of = np.array(cl.node_of)
        self.block = np.array([cpus[0] for cpus in cl.cpus])  # first CPU of every node
        self.rows: dict[str, tuple[Any, Any]] = {}

    def row(self, tid: str, table: dict[str, list[tuple[int, float]]]) -> tuple[Any, Any]:
        if tid not in self.rows:
            self.rows[tid] = (
                self.np.array([n for n, _ in table[tid]]),
                self.np.array([w for _, w in table[tid]], dtype=float),
            )
        return self.rows[tid]


def _lookahead_np(tid, options, children, table, pred, where, finish, cl, vec: _Vectors) -> list[float]:
    """:func:`_lookahead` for every option at once: one row per candidate CPU of ``tid``.

    Same arithmetic in the same order, hence the same floats and the same choices (tests compare both).
    """
    np = vec.np
    f = np.array([o[0] for o in options], dtype=float)
    cpu = np.array([o[1] for o in options])
    rows = np.arange(len(options))
    last = np.tile(np.array(cl.last, dtype=float), (len(options), 1))  # queue ends, per option
    last[rows, cpu] = np.maximum(last[rows, cpu], f)
    tent = {tid: (vec.node_of[cpu], f)}
    worst = f.copy()
    for e in children:
        child = e.dst
        nodes, w = vec.row(child, table)
        base = np.zeros(len(nodes))
        ready = np.zeros((len(options), len(nodes)))
        for pe in pred[child]:
            if pe.src in tent:
                src_nodes, src_finish = tent[pe.src]
                ix = (src_nodes[:, None], nodes[None, :])
                ready = np.maximum(ready, src_finish[:, None] + vec.lat[ix] + pe.data * vec.inv[ix])
            elif pe.src in where:
                q = cl.node_of[where[pe.src]]
                base = np.maximum(base, finish[pe.src] + vec.lat[q, nodes] + pe.data * vec.inv[q, nodes])
        ready = np.maximum(ready, base[None, :])
        node_min = np.minimum.reduceat(last, vec.block, axis=1)[:, nodes]
        eft = np.maximum(ready, node_min) + w[None, :]
        j = np.argmin(eft, axis=1)  # first minimum: the lowest node index
        fin = eft[rows, j]
        chosen = nodes[j]
        # The core: the first one of that node where the child finishes earliest, as the loop version.
        on_node = vec.node_of[None, :] == chosen[:, None]
        c = np.argmin(np.where(on_node, np.maximum(last, ready[rows, j][:, None]), np.inf), axis=1)
        last[rows, c] = fin
        tent[child] = (chosen, fin)
        worst = np.maximum(worst, fin)
    return worst.tolist()


def _cost_table(
    dag: TaskGraph, platform: Platform, allowed: Mapping[str, Iterable[str]]
) -> dict[str, list[tuple[int, float]]]:
    """:meth:`Platform.cost_table` restricted to each task's allowed nodes (only those are priced)."""
    unknown = [t for t in allowed if t not in dag.tasks]
    if unknown:
        raise InputError(f"unknown task {unknown[0]!r} in the allowed nodes", "allowed")
    table: dict[str, list[tuple[int, float]]] = {}
    procs = platform.processors
    for tid, task in dag.tasks.items():
        if tid not in allowed:
            continue
        nodes = list(allowed[tid])
        idx = sorted({platform.index[n] for n in nodes if n in platform.index})
        row = [(i, c) for i in idx if (c := platform.cost(task, procs[i])) is not None]
        if not row:
            raise InputError(f"task {tid!r} cannot run on any of its allowed nodes {sorted(nodes)}", "allowed")
        table[tid] = row
    if len(table) < len(dag.tasks):
        rest = TaskGraph(dag.name, {t: task for t, task in dag.tasks.items() if t not in table}, [])
        table.update(platform.cost_table(rest))
    return {tid: table[tid] for tid in dag.tasks}


# ---- HEFT4K ---------------------------------------------------------------------------------------
def heft4k(
    dag: TaskGraph,
    platform: Platform,
    *,
    lookahead: bool = True,
    rank_mode: str = "mean",
    insertion: bool = True,
    nice_high: int = 0,
    nice_low: int = 19,
    rounding: str = "half-up",
) -> Schedule:
    """HEFT4K: the HEFT (look-ahead) mapping of ``dag`` on the cluster ``platform`` with Eq. 3.16 niceness."""
    plan = map_dag(dag, platform, lookahead=lookahead, rank_mode=rank_mode, insertion=insertion)
    return with_niceness(plan, dag, nice_high=nice_high, nice_low=nice_low, rounding=rounding)


def with_niceness(
    plan: Schedule, dag: TaskGraph, *, nice_high: int = 0, nice_low: int = 19, rounding: str = "half-up"
) -> Schedule:
    """``plan`` with every assignment's niceness set from ``plan.ranks`` (Eq. 3.16)."""
    nice = niceness(plan.ranks, nice_high, nice_low, rounding)
    assignments = [
        Assignment(a.task, a.processor, a.start, a.finish, a.frame, nice[a.task], a.core) for a in plan.assignments
    ]
    critical = sorted(t.id for t in dag.tasks.values() if t.critical)
    params = {**plan.params, "nice_high": nice_high, "nice_low": nice_low, "rounding": rounding}
    metrics = {**plan.metrics, "critical_tasks": critical} if critical else dict(plan.metrics)
    return Schedule(plan.algorithm, assignments, ranks=dict(plan.ranks), params=params, metrics=metrics)


def placements(schedule: Schedule) -> list[dict[str, Any]]:
    """The ``heft4k`` contract's ``placements``: ``[{task, node, niceness, start, finish}]`` (plus ``core``)."""
    return [
        {
            "task": a.task,
            "node": a.processor,
            "niceness": a.niceness,
            "start": a.start,
            "finish": a.finish,
            "core": a.core,
        }
        for a in sorted(schedule.assignments, key=lambda a: (a.start, a.processor, a.task))
    ]


# ---- niceness in a pod ------------------------------------------------------------------------------
def nice_container(
    niceness: int, command: Sequence[str], args: Sequence[str] = (), *, nice_binary: str = "nice"
) -> dict[str, Any]:
    """The container fields that run ``command args`` at ``niceness`` (spec 02 section 7.3).

    Returns ``{"command": [...], "args": [...], "securityContext": {...}}`` to merge into a pod's container
    spec: the entrypoint is wrapped as ``nice -n N -- command args``. A negative niceness (a higher priority
    than the default) needs ``CAP_SYS_NICE``, so ``securityContext.capabilities.add: ["SYS_NICE"]`` is set;
    positive values need no privilege. The pod should carry the annotations ``heft4k/niceness`` and
    ``heft4k/rank`` (the gateway's job) and be pinned to its node (``nodeName`` or a required node affinity).

    Limits (why a real cluster may not behave like the simulator):

    - The image must contain ``nice`` (coreutils or busybox) on its PATH, or pass ``nice_binary``; and the
      original entrypoint must be given, because an image's ENTRYPOINT cannot be read from the manifest
      (``command`` replaces it).
    - ``SYS_NICE`` is outside the Pod Security Standards "baseline" and "restricted" capability lists, so a
      namespace enforcing them rejects pods with negative niceness. A container running as non-root would
      need the capability in its ambient set, which Kubernetes does not grant: there only positive values
      work.
    - Niceness orders threads inside one CPU cgroup. Each pod (and each container in it) is its own cgroup,
      and the kernel first splits CPU time between cgroups by their weight (``cpu.shares``/``cpu.weight``,
      from the CPU request; BestEffort pods all get the minimum), and only then by nice inside a cgroup.
      So between pods on one node niceness alone changes little unless the pods' CPU requests (hence
      cgroup weights) follow the same proportions as the CFS nice weights
      (:data:`continuum.engine.heft4k.cfs_sim.NICE_WEIGHTS`). Do not set CPU limits on DAG pods: CFS quota
      throttling overrides both.
    - Niceness is fixed at start; changing it for a running pod after a partial remap needs a node agent
      calling ``renice`` (e.g. a DaemonSet with ``hostPID`` and ``SYS_NICE``).
    """
    if isinstance(niceness, bool) or not isinstance(niceness, int) or not NICE_MIN <= niceness <= NICE_MAX:
        raise InputError(f"niceness must be an integer in [{NICE_MIN}, {NICE_MAX}], not {niceness!r}", "niceness")
    if not command or not all(isinstance(part, str) and part for part in command):
        raise InputError("the container command must be a non-empty list of strings", "command")
    spec: dict[str, Any] = {
        "command": [nice_binary, "-n", str(niceness), "--", *command],
        "args": list(args),
        "securityContext": {},
    }
    if niceness < 0:
        spec["securityContext"] = {"capabilities": {"add": ["SYS_NICE"]}}
    return spec


register("heft4k", heft4k)
