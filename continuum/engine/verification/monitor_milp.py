"""Monitor allocation MILP (thesis §3.5, Eqs. 3.21-3.22; spec 03 §10-§11.2).

The coordinator places every monitor on one computing unit so that the total delay of the topics the
monitors receive is minimal and no unit exceeds its CPU budget. Linear 0/1 form (spec 03 §10.2), with
monitors i, units j, topics k and S_k the monitors whose assertion reads topic k::

    minimise   Σ_k Σ_j delay[k,j]·y[k,j]  +  ε·Σ_i (1 - x[i,cur(i)])
    subject to Σ_j x[i,j] = 1                                                   for every monitor i
               y[k,j] >= x[i,j]                                                 for every k, i in S_k, j
               Σ_i monitorCPU[i,j]·x[i,j] + Σ_k topicCPU[k,j]·y[k,j] <= cap[j]   for every unit j
    x binary, 0 <= y <= 1 (y is integral at the optimum: it is pushed down to max_i x[i,j])

Readings (spec 03 §15 #10-#12 and §10.2 proposals), each a parameter:
  * ``literal_topic_coupling=False``: Eq. 3.21 read literally ORs over *all* monitors (a unit that hosts
    any monitor receives every topic); the default charges a topic only where a monitor reading it runs.
  * ``cap[j] = max(0, availableCPU[j] - (100 - threshold[j]))`` keeps the unit's total CPU under its
    threshold (100 when none is given).
  * ``epsilon = 1e-3`` migration penalty: among equally good allocations the current one wins, so an
    unchanged input causes no migration. The solves' optimality gap is absolute and below it (epsilon / 2,
    not HiGHS's relative 1e-4, which on objectives above 10 let a solve stop at a needless migration).
  * Statistics of a monitor on a unit where it never ran: the last value observed there
    (:class:`MonitorAllocator` keeps them), else the value on its current unit scaled by
    ``speed[cur] / speed[j]`` (``speed`` is an optional per-node field, default 1).
  * SMA(``window=10``) low-pass filter over the statistics fed to the MILP (:class:`StatsFilter`).
  * Infeasible means overload: the capacity rows get slacks s_j >= 0; the total overload Σ s_j is
    minimised first and the delay second (lexicographically, in two solves, instead of a big-M weight).
    Units with s_j > 0 are *overloaded* and :func:`overload_plan` applies the two strategies of §11.2:
    strategy 1 raises each monitor's priority with its active instances; strategy 2 lets monitors marked
    ``tolerant`` drop old events (with a monitor reset), lowest priority first, until they cover the excess.

How it is solved (equivalent to the form above, faster):

* Classes: monitors with identical statistics form a class and the model counts them per unit (n[c,j],
  integer) instead of placing them one by one; a binary z[g,j] says that some monitor reading topic set
  g runs on j (n[c,j] <= |c|·z[g,j], y[k,j] >= z[g,j]).
* Blocks (:func:`_decomposed`): monitors that share no topic and no current unit only interact through
  capacities; each block is solved alone with full capacities (a relaxation whose optima add up to a
  lower bound) and when the union fits it is optimal; blocks that overfill a shared unit are merged and
  solved again. With robot-local assertions this is one small model per robot.
* Valid inequalities that keep the optimum but tighten the LP relaxation (hard capacities only):
  "spread" cuts Σ_j z[g,j] >= L_g (a group too big for any one unit) and relief covers
  (:func:`_relief_covers`): an overloaded unit must shed load, so the topics of the monitors leaving it
  must be received elsewhere; an extended formulation over the relief topic sets makes the LP pay for
  them (on the 1000 x 20 robot-local fleet the root bound goes from 191 to 333, optimum 342). Host covers
  (:func:`_host_covers`) are the receiving side: when the other units cannot hold every monitor (each
  counted for the most monitors its capacity fits), unit j must host the rest, so the topics it receives
  must hold that many monitors (cross-robot 500 x 5 fleet, where the cloud takes the overflow: root
  bound 668 -> 824).
* The matrix is assembled with numpy/scipy.sparse in one go; HiGHS (highspy) solves it, warm-started with
  the better of two seeds, each improved by local search (:func:`_improve`): a repair heuristic, and
  (``"covers"``) a robot-level one (:func:`_partition`) that decides which unit hosts each overloaded
  unit's overflow (kept together, so that the host receives its topics once) and then moves and swaps
  those host choices, every candidate evaluated exactly. The MILP restricted to the seed's neighbourhood
  (each monitor on its current unit or on a unit hosting monitors of the same current unit; one node,
  :func:`_neighbourhood`) improves it first. Both searches are skipped on models of at most
  ``SEED_SEARCH_PAIRS`` (class, unit) pairs, which HiGHS solves in a few ms anyway, and a seed at the
  trivial bound (every topic read received once, where it arrives soonest, no migration) is returned as
  optimal without a solver (:func:`_at_lower_bound`). Then the whole MILP runs within a time limit (the allocation
  period) or a budget of branch-and-bound nodes (``work_limit``, reproducible); past it the best
  allocation found, polished by the same local search, is returned with its optimality gap.
* ``formulation`` keeps the earlier models selectable for comparison: ``"textbook"`` (the form above,
  one x[i,j] per monitor), ``"classes"`` (classes, blocks, spread cuts, relief covers) and ``"covers"``
  (default: + host covers and the local search). tests/engine/verification/test_monitor_milp_formulations.py
  checks all three against brute force on small instances, and that every cut holds for every feasible
  allocation.

Measured by benchmarks/milp_scaling.py --formulations covers,classes,textbook --time-limit 10 (shared
2-core machine, load average 6-7: CPU seconds of the solving process; wall time was about twice that):

* robot-local fleets (one block per robot), 1000 monitors x 20 units: optimal in 0.91 s (uniform) and
  2.9 s (heterogeneous), "classes" 1.1 s and 4.2 s, the textbook model stops at the limit without a root
  bound. 500 x 5 and 500 x 10 (a few robots sharing one or two intermediate units): stopped at the limit
  with gap 9 % and 5 % (covers) against 24 % and 30 % (classes) and 53 % and 55 % (textbook).
* Not met, cross-robot reads (10 % of the monitors read a second robot's topic, everything is one
  block): 500 x 5/10/20 stop with gaps of 24-76 %, and at 1000 x 20 the root LP (~10 s CPU on its own)
  does not finish within the limit. The root bound there (~635 at 1000 x 20, 304 at 500 x 10) is not
  weak because of the y >= z linking: the LP receives each topic once, spread in fractions over the
  intermediate units, and hosts a fraction of every monitor on each, so that cross-robot reads cost
  nothing; an integer allocation partitions the robots among those units and pays for the reads that
  cross the partition. A bound that sees this needs per-unit patterns (Dantzig-Wolfe / column
  generation); not done, and the bound is unchanged. What the covers formulation improves there is the
  allocation returned. The old seed (repair + local search) had delay 1258 at 500 x 10 uniform (922
  heterogeneous) and 1361 (1415) at 1000 x 20, where HiGHS given 900 s reaches 412 at 500 x 10 uniform
  with a bound of 333. The robot-level seed (:func:`_partition` + :func:`_improve`) gives 621 (569) in
  0.3 s CPU and 1124 (1107) in 1.8 s; the neighbourhood step then 545 (442) in ~1 s and 970 (1000) in
  ~10 s. Side by side (load 3-9): at 1000 x 20 with --time-limit 30, delay 1361 -> 970 (uniform, gap
  53 % -> 34 % against the root bound 636) and 1414 -> 1000 (heterogeneous, no bound reached by either),
  17-29 s CPU (the neighbourhood step gets at most half of the time left; with --time-limit 10, load
  2-5: 1361 -> 980 and 1414 -> 1000, and neither reaches the root bound, which the old code reached for
  the uniform fleet, gap 53 %); at 500 x 10 with --time-limit 10, 577 -> 544 (gap 47 % -> 44 %) and
  922 -> 442 (67 % -> 32 %), and with ``work_limit=1`` (the root node only, where HiGHS's own
  heuristics also improve the start) 577 -> 544 and 447 -> 436, 10 -> 14 s and 26 -> 36 s CPU (gaps
  44 % and 30 % against root bounds 307 and 304).
  On the robot-local fleets the seed costs 0.2-0.6 s CPU per solve (1000 x 20: 0.47 -> 0.64 s and
  1.30 -> 1.61 s at load 2-5, 0.74 -> 0.96 s and 1.72 -> 2.34 s at load 6, all optimal) and finds 245
  (gap 5 %) where the heterogeneous 500 x 10 fleet had 331 (gap 30 %) at the limit.
* The root node is not capped by ``work_limit``: at 1000 x 20 cross-robot it takes ~85 s CPU (its LP
  ~10 s; at 300 x 15, 16 of the root's 22 s are HiGHS's sub-MIP heuristics, RINS/RENS). HiGHS 1.15.1
  did not stop a MIP at ``simplex_iteration_limit`` (2,000 changed nothing at 500 x 10) and its
  callback reports no LP iteration count, so highspy offers no LP-work cap; switching the sub-MIP
  heuristics off takes kairos_monitors from 19.0 to 15.3 s CPU but changes its allocations, so it is
  not done.
"""

from __future__ import annotations

import math
import time
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import highspy
import numpy as np
from scipy.sparse import coo_matrix, csr_matrix

from continuum.engine.core.errors import InputError

__all__ = [
    "FORMAT",
    "HIGHS_OPTIONS",
    "Allocation",
    "MonitorAllocator",
    "MonitorStats",
    "StatsFilter",
    "allocate",
    "complete_cpu",
    "overload_plan",
]

FORMAT = "continuum.monitorstats/v1"
FORMULATIONS = ("covers", "classes", "textbook")  # see allocate()


# ===================================================================================================
# Statistics (the continuum.monitorstats/v1 contract)
# ===================================================================================================


@dataclass
class MonitorStats:
    nodes: list[str]
    available: dict[str, float]
    threshold: dict[str, float]
    speed: dict[str, float]
    topics: list[str]
    delay: dict[str, dict[str, float]]  # topic -> node -> ms
    topic_cpu: dict[str, dict[str, float]]  # topic -> node -> % of the node
    monitors: list[str]
    monitor_topics: dict[str, list[str]]
    monitor_cpu: dict[str, dict[str, float]]  # monitor -> node -> % (possibly partial)
    current: dict[str, str | None]
    tolerant: dict[str, bool] = field(default_factory=dict)
    active_instances: dict[str, int] = field(default_factory=dict)

    @classmethod
    def from_dict(cls, doc: Mapping) -> MonitorStats:
        """Validate a ``continuum.monitorstats/v1`` document; every error names the offending element."""
        if not isinstance(doc, Mapping):
            raise InputError("monitor statistics must be a JSON object")
        if doc.get("format", FORMAT) != FORMAT:
            raise InputError(f"format must be {FORMAT!r}, not {doc.get('format')!r}", field="format")
        nodes, available, threshold, speed = _nodes(doc.get("nodes"))
        topics, delay, topic_cpu = _topics(doc.get("topics", []), nodes)
        stats = cls(nodes, available, threshold, speed, topics, delay, topic_cpu, [], {}, {}, {})
        _monitors(doc.get("monitors", []), stats)
        return stats

    def copy(self) -> MonitorStats:
        return MonitorStats(
            list(self.nodes),
            dict(self.available),
            dict(self.threshold),
            dict(self.speed),
            list(self.topics),
            {k: dict(v) for k, v in self.delay.items()},
            {k: dict(v) for k, v in self.topic_cpu.items()},
            list(self.monitors),
            {k: list(v) for k, v in self.monitor_topics.items()},
            {k: dict(v) for k, v in self.monitor_cpu.items()},
            dict(self.current),
            dict(self.tolerant),
            dict(self.active_instances),
        )

    def capacity(self) -> dict[str, float]:
        return {j: max(0.0, self.available[j] - (100.0 - self.threshold[j])) for j in self.nodes}


def _number(value: Any, where: str, minimum: float | None = 0.0, maximum: float | None = None) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{where}: expected a number, got {value!r}")
    if minimum is not None and value < minimum:
        raise InputError(f"{where}: must be >= {minimum:g}, got {value:g}")
    if maximum is not None and value > maximum:
        raise InputError(f"{where}: must be <= {maximum:g}, got {value:g}")
    return float(value)


def _name(item: Any, where: str) -> str:
    if not isinstance(item, Mapping):
        raise InputError(f"{where}: expected an object")
    name = item.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"{where}: missing 'name'")
    return name


def _nodes(items: Any):
    if not isinstance(items, list) or not items:
        raise InputError("'nodes' must be a non-empty list", field="nodes")
    nodes, available, threshold, speed = [], {}, {}, {}
    for n, item in enumerate(items):
        name = _name(item, f"nodes[{n}]")
        if name in available:
            raise InputError(f"node {name!r} is listed twice", field="nodes")
        nodes.append(name)
        available[name] = _number(item.get("available_cpu"), f"node {name!r}: available_cpu", 0, 100)
        threshold[name] = _number(item.get("threshold", 100), f"node {name!r}: threshold", 0, 100)
        speed[name] = _number(item.get("speed", 1.0), f"node {name!r}: speed", 1e-9)
    return nodes, available, threshold, speed


def _per_node(values: Any, where: str, nodes: Sequence[str]) -> dict[str, float]:
    if values is None:
        return {}
    if not isinstance(values, Mapping):
        raise InputError(f"{where}: expected an object mapping node names to numbers")
    out = {}
    for node, v in values.items():
        if node not in nodes:
            raise InputError(f"{where}: unknown node {node!r}")
        out[node] = _number(v, f"{where}[{node}]")
    return out


def _topics(items: Any, nodes: list[str]):
    if not isinstance(items, list):
        raise InputError("'topics' must be a list", field="topics")
    topics, delay, cpu = [], {}, {}
    for n, item in enumerate(items):
        name = _name(item, f"topics[{n}]")
        if name in delay:
            raise InputError(f"topic {name!r} is listed twice", field="topics")
        topics.append(name)
        delay[name] = _per_node(item.get("delay"), f"topic {name!r}: delay", nodes)
        cpu[name] = _per_node(item.get("cpu"), f"topic {name!r}: cpu", nodes)
    return topics, delay, cpu


def _monitors(items: Any, stats: MonitorStats) -> None:
    if not isinstance(items, list):
        raise InputError("'monitors' must be a list", field="monitors")
    for n, item in enumerate(items):
        name = _name(item, f"monitors[{n}]")
        if name in stats.monitor_cpu:
            raise InputError(f"monitor {name!r} is listed twice", field="monitors")
        reads = item.get("topics", [])
        if not isinstance(reads, list) or not all(isinstance(t, str) for t in reads):
            raise InputError(f"monitor {name!r}: 'topics' must be a list of topic names")
        for t in reads:
            if t not in stats.delay:
                raise InputError(f"monitor {name!r}: unknown topic {t!r}")
            missing = [j for j in stats.nodes if j not in stats.delay[t]]
            if missing:
                raise InputError(f"topic {t!r} (read by monitor {name!r}): no delay for node {missing[0]!r}")
        current = item.get("current")
        if current is not None and (not isinstance(current, str) or current not in stats.available):
            raise InputError(f"monitor {name!r}: current node {current!r} is not a listed node")
        cpu = _per_node(item.get("cpu"), f"monitor {name!r}: cpu", stats.nodes)
        if not cpu:
            raise InputError(f"monitor {name!r}: no CPU statistic on any node")
        stats.monitors.append(name)
        stats.monitor_topics[name] = list(dict.fromkeys(reads))
        stats.monitor_cpu[name] = cpu
        stats.current[name] = current
        stats.tolerant[name] = bool(item.get("tolerant", item.get("allow_event_dropping", False)))
        stats.active_instances[name] = int(_number(item.get("active_instances", 0), f"monitor {name!r}: active"))


# ===================================================================================================
# Filtering and completing the statistics
# ===================================================================================================


class StatsFilter:
    """Simple moving average over the last ``window`` statistics (spec 03 §10.2, SMA(10))."""

    def __init__(self, window: int = 10):
        if window < 1:
            raise InputError("stats filter window must be >= 1", field="window")
        self.window = window
        self._series: dict[tuple, deque[float]] = {}

    def _avg(self, key: tuple, value: float) -> float:
        series = self._series.setdefault(key, deque(maxlen=self.window))
        series.append(value)
        return sum(series) / len(series)

    def update(self, stats: MonitorStats) -> MonitorStats:
        out = stats.copy()
        for j in out.nodes:
            out.available[j] = self._avg(("avail", j), stats.available[j])
        for k in out.topics:
            for j, v in stats.delay[k].items():
                out.delay[k][j] = self._avg(("delay", k, j), v)
            for j, v in stats.topic_cpu[k].items():
                out.topic_cpu[k][j] = self._avg(("tcpu", k, j), v)
        for i in out.monitors:
            for j, v in stats.monitor_cpu[i].items():
                out.monitor_cpu[i][j] = self._avg(("mcpu", i, j), v)
        return out


def complete_cpu(stats: MonitorStats, observed: Mapping[tuple[str, str], float] | None = None) -> np.ndarray:
    """monitorCPU[i, j] for every unit: measured, else last observed there, else scaled by node speed."""
    observed = observed or {}
    cpu = np.zeros((len(stats.monitors), len(stats.nodes)))
    for a, i in enumerate(stats.monitors):
        given = stats.monitor_cpu[i]
        now_on = stats.current[i]
        cur = now_on if now_on is not None and now_on in given else next(iter(given))
        for b, j in enumerate(stats.nodes):
            if j in given:
                cpu[a, b] = given[j]
            elif (i, j) in observed:
                cpu[a, b] = observed[(i, j)]
            else:
                cpu[a, b] = given[cur] * stats.speed[cur] / stats.speed[j]
    return cpu


# ===================================================================================================
# The MILP
# ===================================================================================================


@dataclass
class Allocation:
    feasible: bool
    objective: float  # Σ delay of the topics received (ms), without the ε term
    allocation: dict[str, str]
    cpu: dict[str, float]  # planned CPU share per node (% of the node)
    capacity: dict[str, float]
    overloaded: dict[str, float]  # node -> CPU over its capacity (only when infeasible)
    migrations: list[str]
    received: dict[str, list[str]]  # node -> topics it must receive
    solve_time_ms: float
    status: str  # "optimal", "time_limit" (feasible, not proven optimal) or "overloaded"
    gap: float = 0.0
    priorities: dict[str, int] = field(default_factory=dict)
    drop_events: list[str] = field(default_factory=list)
    unresolved: dict[str, float] = field(default_factory=dict)
    blocks: int = 1  # independent blocks the model was split into (see _decomposed)
    reused: bool = False  # MonitorAllocator: same statistics as the previous period, not solved again
    # Diagnostics (not part of to_dict): HiGHS's dual bounds on the model objective (delay + 1e-6·Σy -
    # ε·monitors kept; summed over blocks), after the root node and at the end, and the B&B nodes.
    root_bound: float = -math.inf
    bound: float = -math.inf
    nodes: int = 0

    def to_dict(self) -> dict:
        return {
            "feasible": self.feasible,
            "objective": self.objective,
            "allocation": self.allocation,
            "cpu": self.cpu,
            "capacity": self.capacity,
            "overloaded": self.overloaded,
            "migrations": self.migrations,
            "received": self.received,
            "priorities": self.priorities,
            "drop_events": self.drop_events,
            "unresolved_overload": self.unresolved,
            "solve_time_ms": self.solve_time_ms,
            "status": self.status,
            "gap": self.gap,
            "blocks": self.blocks,
            "reused": self.reused,
        }


@dataclass
class _Classes:
    """Monitors with identical statistics (topics, CPU per unit, current unit) are interchangeable: the
    model counts how many of each class go to each unit instead of placing them one by one, which removes
    the symmetry that otherwise makes branch-and-bound enumerate equivalent allocations."""

    members: list[list[int]]  # class -> monitor indices
    cpu: np.ndarray  # class x unit
    current: list[int | None]  # class -> unit index
    group: list[int]  # class -> topic-set group
    group_topics: list[list[int]]  # group -> topic indices
    allowed: np.ndarray | None = None  # class x unit, when candidate units are restricted


def _topic_matrices(stats: MonitorStats) -> tuple[np.ndarray, np.ndarray]:
    """(delay in ms, topic CPU in %), topic x unit: the statistics' per-topic dicts as arrays (0 where absent)."""
    shape = (len(stats.topics), len(stats.nodes))
    delay = np.array([[stats.delay[k].get(j, 0.0) for j in stats.nodes] for k in stats.topics], dtype=float)
    tcpu = np.array([[stats.topic_cpu[k].get(j, 0.0) for j in stats.nodes] for k in stats.topics], dtype=float)
    return delay.reshape(shape), tcpu.reshape(shape)


def _classes(stats: MonitorStats, cpu: np.ndarray, literal: bool, merge: bool = True) -> _Classes:
    node_ix = {j: b for b, j in enumerate(stats.nodes)}
    topic_ix = {k: t for t, k in enumerate(stats.topics)}
    by_key: dict[tuple, int] = {}
    groups: dict[tuple, int] = {}
    members: list[list[int]] = []
    current: list[int | None] = []
    group: list[int] = []
    for a, i in enumerate(stats.monitors):
        topics = (
            tuple(range(len(stats.topics))) if literal else tuple(sorted(topic_ix[k] for k in stats.monitor_topics[i]))
        )
        now_on = stats.current[i]
        cur = None if now_on is None else node_ix[now_on]
        key = (topics, cur, cpu[a].tobytes()) if merge else (a,)
        if key not in by_key:
            by_key[key] = len(members)
            members.append([])
            current.append(cur)
            group.append(groups.setdefault(topics, len(groups)))
        members[by_key[key]].append(a)
    group_topics = [list(t) for t in sorted(groups, key=lambda t: groups[t])]
    class_cpu = np.array([cpu[m[0]] for m in members])
    return _Classes(members, class_cpu, current, group, group_topics)


@dataclass
class _Model:
    c: np.ndarray
    a: csr_matrix
    lo: np.ndarray
    hi: np.ndarray
    integrality: np.ndarray
    ub: np.ndarray
    n_x: int
    y0: int
    z0: int
    s0: int
    w0: int = 0  # start of the cover-family choice variables (hard-capacity models only)
    families: list[_Family] = field(default_factory=list)
    epsilon: float = 0.0  # the migration penalty in ``c``: the solve's gap must stay below it (_solve)


def _build(
    stats: MonitorStats,
    cl: _Classes,
    epsilon: float,
    slack: bool,
    delay_weight: float = 1.0,
    max_excess: float | None = None,
    formulation: str = "covers",
) -> _Model:
    """Variables: n[c,j] (monitors of class c on unit j, integer), y[k,j] (topic k received on j),
    z[g,j] (some monitor of topic-set group g on j, binary), [s_j capacity slacks]."""
    j_count, k_count = len(stats.nodes), len(stats.topics)
    c_count, g_count = len(cl.members), len(cl.group_topics)
    n_x, n_y, n_z, n_s = c_count * j_count, k_count * j_count, g_count * j_count, j_count if slack else 0
    y0, z0, s0 = n_x, n_x + n_y, n_x + n_y + n_z
    n = s0 + n_s
    size = np.array([len(m) for m in cl.members], dtype=float)
    delay, tcpu = (matrix.reshape(-1) for matrix in _topic_matrices(stats))
    units = np.arange(j_count)

    c = np.zeros(n)
    c[y0:z0] = delay_weight * delay + 1e-6  # the tiny cost keeps unneeded topics unreceived
    for a, cur in enumerate(cl.current):
        if cur is not None:
            c[a * j_count + cur] -= epsilon
    if slack:
        c[s0:] = 1.0 if delay_weight == 0 else 0.0

    rows: list[np.ndarray] = []
    cols: list[np.ndarray] = []
    vals: list[np.ndarray] = []
    lo: list[np.ndarray] = []
    hi: list[np.ndarray] = []
    count = 0

    def add(r: np.ndarray, col: np.ndarray, v: np.ndarray, n_rows: int, low: np.ndarray, high: np.ndarray) -> None:
        nonlocal count
        rows.append(r + count)
        cols.append(col)
        vals.append(v)
        lo.append(low)
        hi.append(high)
        count += n_rows

    # Σ_j n[c,j] = |c|
    add(np.repeat(np.arange(c_count), j_count), np.arange(n_x), np.ones(n_x), c_count, size, size)
    # n[c,j] - |c|·z[g(c),j] <= 0
    r = np.arange(n_x)
    zcol = z0 + (np.repeat(np.array(cl.group), j_count) * j_count + np.tile(units, c_count))
    add(
        np.concatenate([r, r]),
        np.concatenate([r, zcol]),
        np.concatenate([np.ones(n_x), -np.repeat(size, j_count)]),
        n_x,
        np.full(n_x, -np.inf),
        np.zeros(n_x),
    )
    # z[g,j] - y[k,j] <= 0 for k in T_g
    pairs = np.array([(g, k) for g, ks in enumerate(cl.group_topics) for k in ks], dtype=int).reshape(-1, 2)
    m = len(pairs) * j_count
    if m:
        zc = z0 + (pairs[:, 0:1] * j_count + units).reshape(-1)
        yc = y0 + (pairs[:, 1:2] * j_count + units).reshape(-1)
        r = np.arange(m)
        add(
            np.concatenate([r, r]),
            np.concatenate([zc, yc]),
            np.concatenate([np.ones(m), -np.ones(m)]),
            m,
            np.full(m, -np.inf),
            np.zeros(m),
        )
    cap = stats.capacity()
    if not slack and formulation != "textbook":  # spread cuts: valid only when capacities are hard
        for g, need in _spread_bounds(cl, [cap[j] for j in stats.nodes], by="group"):
            add(
                np.zeros(j_count, dtype=int),
                z0 + g * j_count + units,
                np.ones(j_count),
                1,
                np.array([need]),
                np.array([np.inf]),
            )
        for k, need in _spread_bounds(cl, [cap[j] for j in stats.nodes], by="topic"):
            add(
                np.zeros(j_count, dtype=int),
                y0 + k * j_count + units,
                np.ones(j_count),
                1,
                np.array([need]),
                np.array([np.inf]),
            )
    families: list[_Family] = []

    def row(columns: list[int], coefs: list[float], low: float, high: float) -> None:
        add(np.zeros(len(columns), dtype=int), np.array(columns, dtype=int), np.array(coefs, dtype=float), 1,
            np.array([low]), np.array([high]))  # fmt: skip

    if not slack and formulation != "textbook":  # relief (and host) covers: valid only for hard capacities
        families, cover_cuts = _relief_covers(stats, cl)
        if formulation == "covers":
            host_families, host_cuts = _host_covers(stats, cl, max_sets=HOST_SETS)
            families += host_families
        else:
            host_cuts = []
        for unit, topics, need in cover_cuts:
            columns = [y0 + k * j_count + b for k in topics for b in range(j_count) if b != unit]
            row(columns, [1.0] * len(columns), float(need), np.inf)
        for unit, topics, need in host_cuts:
            columns = [y0 + k * j_count + unit for k in topics]
            row(columns, [1.0] * len(columns), float(need), np.inf)
        w = n
        for fam in families:
            fam.w0 = w
            # exactly one relief (host) set is chosen ...
            row([w + o for o in range(len(fam.sets))], [1.0] * len(fam.sets), 1.0, 1.0)
            if fam.complete and not fam.host:  # ... a monitor of the unit leaves only if that set holds
                for cls in fam.members:  # all its topics ...
                    held = set(cl.group_topics[cl.group[cls]])
                    wcols = [w + o for o, topics in enumerate(fam.sets) if held <= set(topics)]
                    row([cls * j_count + fam.unit, *wcols], [1.0] + [size[cls]] * len(wcols), size[cls], np.inf)
            if fam.complete and fam.host:  # ... (host: a monitor runs on the unit only if the set holds all
                for cls in fam.members:  # its topics) ...
                    held = set(cl.group_topics[cl.group[cls]])
                    wcols = [w + o for o, topics in enumerate(fam.sets) if held <= set(topics)]
                    row([cls * j_count + fam.unit, *wcols], [1.0] + [-size[cls]] * len(wcols), -np.inf, 0.0)
            # ... and each of its topics is received on some other unit (host: on the unit itself)
            for k in sorted({k for o in fam.sets for k in o}):
                if fam.host:
                    ycols = [y0 + k * j_count + fam.unit]
                else:
                    ycols = [y0 + k * j_count + b for b in range(j_count) if b != fam.unit]
                wcols = [w + o for o, topics in enumerate(fam.sets) if k in topics]
                row(ycols + wcols, [1.0] * len(ycols) + [-1.0] * len(wcols), 0.0, np.inf)
            w += len(fam.sets)
        n_w = w - n
        n = w
        c = np.concatenate([c, np.zeros(n_w)])
    # capacity: Σ cpu·n + Σ topicCPU·y - s <= cap
    cr = [np.tile(units, c_count), np.tile(units, k_count)]
    cc = [np.arange(n_x), y0 + np.arange(n_y)]
    cv = [cl.cpu.reshape(-1), tcpu]
    if slack:
        cr.append(units)
        cc.append(s0 + units)
        cv.append(-np.ones(j_count))
    add(
        np.concatenate(cr),
        np.concatenate(cc),
        np.concatenate(cv),
        j_count,
        np.full(j_count, -np.inf),
        np.array([cap[j] for j in stats.nodes]),
    )

    if slack and max_excess is not None:  # phase 2 of the overload solve: keep the minimum total excess
        add(np.zeros(j_count, dtype=int), s0 + units, np.ones(j_count), 1, np.array([-np.inf]), np.array([max_excess]))
    a = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(count, n)).tocsr()
    w0 = s0 + n_s
    integrality = np.zeros(n)
    integrality[:n_x] = 1
    integrality[z0:s0] = 1
    integrality[w0:] = 1
    ub = np.ones(n)
    ub[:n_x] = np.repeat(size, j_count)
    if cl.allowed is not None:
        ub[:n_x] *= cl.allowed.reshape(-1)
    ub[s0:w0] = np.inf
    return _Model(c, a, np.concatenate(lo), np.concatenate(hi), integrality, ub, n_x, y0, z0, s0, w0, families, epsilon)


@dataclass
class _Family:
    """Topic sets whose reception elsewhere would let an overloaded unit shed enough load: every such
    set (``complete``) or only the minimal ones."""

    unit: int
    sets: list[list[int]]
    complete: bool
    members: list[int]  # the classes counted in the unit's load
    universe: set[int] = field(default_factory=set)  # the topics the sets are drawn from
    w0: int = 0
    host: bool = False  # a host family (see _host_covers): the sets are what the unit itself receives


def _heaviest_topics(
    cl: _Classes, members: list[int], weight_of: Callable[[int], float], universe: list[int], max_topics: int
) -> tuple[list[int], list[int]]:
    """The ``max_topics`` topics of ``universe`` read by the most weight of ``members`` (ties by index), sorted,
    and the members whose topics all stay: a cover over them is still valid, only smaller."""
    weight: dict[int, float] = {}
    for c in members:
        for k in cl.group_topics[cl.group[c]]:
            weight[k] = weight.get(k, 0.0) + weight_of(c)
    kept = set(sorted(universe, key=lambda k: (-weight[k], k))[:max_topics])
    return sorted(kept), [c for c in members if set(cl.group_topics[cl.group[c]]) <= kept]


def _relief_covers(
    stats: MonitorStats, cl: _Classes, max_topics: int = 14, max_sets: int = 64, max_cuts: int = 128
) -> tuple[list[_Family], list[tuple[int, list[int], int]]]:
    """Relief-cover inequalities for units that cannot keep all the monitors now running on them.

    Let D be the classes whose current unit is r, load(c) = |c|·monitorCPU[c,r] and E = Σ_D load - cap[r]
    > 0. The monitors of D that stay on r fit in cap[r], so monitors of D carrying at least E must run
    elsewhere, and a monitor only runs on a unit j that receives all its topics. With O the set of topics
    received on some unit j != r, L(O) = Σ{load(c) : c in D, topics(c) ⊆ O} >= E must hold. (Any D is
    valid; adding the classes whose topics all arrive soonest on r tightened the bound but slowed HiGHS
    down on the RB-Kairos simulation, 13.7 s -> 24.4 s for 31 periods.) Valid forms added (they hold for
    every integer allocation, so optimality is unchanged):

    * an extended formulation: choose the relief set (w, Σ w = 1), receive each of its topics elsewhere,
      Σ_{j != r} y[k,j] >= Σ_{O ∋ k} w[O], and let a monitor of D leave r only if the chosen set holds its
      topics, |c| - n[c,r] <= |c|·Σ_{O ⊇ topics(c)} w[O] (every relief set when they are few; else only the
      minimal ones, without the leave rows);
    * when there are too many minimal sets: Σ_{k ∉ S} Σ_{j != r} y[k,j] >= m(S) for every maximal S, where
      m(S) is the fewest topics outside S that complete S to a relief set.

    Without them the LP relaxation moves a sliver of every monitor (receiving every topic fractionally);
    with them the root bound is close to the integer optimum on the overloaded-edge instances of
    benchmarks/milp_scaling.py (e.g. 191 -> 333 of 342 for 1000 monitors on 20 units).
    """
    cap = stats.capacity()
    families: list[_Family] = []
    cuts: list[tuple[int, list[int], int]] = []
    for r, unit in enumerate(stats.nodes):
        members = [c for c in range(len(cl.members)) if cl.current[c] == r]
        if not members:
            continue
        load = {c: float(cl.cpu[c, r]) * len(cl.members[c]) for c in members}
        excess = sum(load.values()) - cap[unit]
        if excess <= 1e-9:
            continue
        universe = sorted({k for c in members for k in cl.group_topics[cl.group[c]]})
        if len(universe) > max_topics:  # keep the topics carrying most load; the rest stays valid with a
            # smaller D (only classes within the kept topics count)
            universe, members = _heaviest_topics(cl, members, load.__getitem__, universe, max_topics)
            excess = sum(load[c] for c in members) - cap[unit]
            if excess <= 1e-9:
                continue
        every, minimal, unit_cuts = _relief_sets(
            universe, [(cl.group_topics[cl.group[c]], load[c]) for c in members], excess
        )
        if not minimal:
            continue  # even receiving every topic elsewhere is not enough: the MILP proves it infeasible
        if every and len(every) <= max_sets:
            families.append(_Family(r, every, True, members, set(universe)))
        elif len(minimal) <= max_sets:
            families.append(_Family(r, minimal, False, members, set(universe)))
        else:
            cuts.extend((r, topics, need) for topics, need in unit_cuts[:max_cuts])
    return families, cuts


def _host_covers(
    stats: MonitorStats, cl: _Classes, max_topics: int = 14, max_sets: int = 64, max_cuts: int = 128
) -> tuple[list[_Family], list[tuple[int, list[int], int]]]:
    """Host-cover inequalities for units that must host some monitors because the others cannot.

    A unit j' != j hosts at most h[j'] monitors: the most of the smallest monitorCPU[·, j'] whose sum
    fits in cap[j'] (topic CPU only lowers it). So unit j hosts at least R = N - Σ_{j' != j} h[j']
    monitors, and a monitor runs on j only if j receives all its topics: with O the set of topics
    received on j, #{monitors whose topics ⊆ O} >= R. This is the receiving side of the relief covers
    (:func:`_relief_covers`, which look at what an overloaded unit must shed); the same subset machinery
    gives its valid forms, with y[k,j] on j itself instead of Σ_{j' != r} y[k,j']:

    * choose the host set (w, Σ w = 1), y[k,j] >= Σ_{O ∋ k} w[O], and, when every host set is listed,
      n[c,j] <= |c|·Σ_{O ⊇ topics(c)} w[O] (the chosen O is the received set itself, which is a host set);
    * else Σ_{k ∉ S} y[k,j] >= m(S), the fewest topics outside S that complete S to a host set.

    With a universe cut to ``max_topics`` topics, the monitors reading a topic outside it are dropped and
    R lowered by their number (they may all be on j): still valid. On the cross-robot fleets of
    benchmarks/milp_scaling.py, where the slow cloud must take the overflow of every robot, the LP
    relaxation otherwise receives a fraction of every topic there.
    """
    cap = stats.capacity()
    sizes = np.array([len(m) for m in cl.members])
    total = int(sizes.sum())
    hosts = []
    for b, unit in enumerate(stats.nodes):
        per = np.repeat(cl.cpu[:, b], sizes)
        per.sort()
        hosts.append(int(np.searchsorted(np.cumsum(per), cap[unit] + 1e-9, side="right")))
    families: list[_Family] = []
    cuts: list[tuple[int, list[int], int]] = []
    for b in range(len(stats.nodes)):
        need = total - (sum(hosts) - hosts[b])
        if need <= 0:
            continue
        members = list(range(len(cl.members)))
        universe = sorted({k for c in members for k in cl.group_topics[cl.group[c]]})
        if len(universe) > max_topics:
            universe, members = _heaviest_topics(cl, members, sizes.__getitem__, universe, max_topics)
            need -= total - int(sizes[members].sum())
            if need <= 0:
                continue
        every, minimal, unit_cuts = _relief_sets(
            universe, [(cl.group_topics[cl.group[c]], float(sizes[c])) for c in members], float(need)
        )
        if not minimal:
            continue  # no topic set hosts enough: the MILP proves it infeasible
        if every and len(every) <= max_sets:
            families.append(_Family(b, every, True, members, set(universe), host=True))
        elif len(minimal) <= max_sets:
            families.append(_Family(b, minimal, False, members, set(universe), host=True))
        else:
            cuts.extend((b, topics, need) for topics, need in unit_cuts[:max_cuts])
    return families, cuts


def _relief_sets(
    universe: list[int], classes: list[tuple[list[int], float]], excess: float
) -> tuple[list[list[int]], list[list[int]], list[tuple[list[int], int]]]:
    """Every relief set over ``universe`` (empty when there are very many), the minimal ones, and the
    m(S) cuts (subset sums by a zeta transform)."""
    u = len(universe)
    pos = {k: b for b, k in enumerate(universe)}
    full = np.arange(1 << u)
    sums = np.zeros(1 << u)
    for topics, load in classes:
        sums[sum(1 << pos[k] for k in topics)] += load
    for b in range(u):  # sums[S] = Σ of the classes whose topic mask is a subset of S
        has = (full >> b) & 1 == 1
        sums[has] += sums[full[has] ^ (1 << b)]
    feasible = sums >= excess - 1e-9
    if not feasible[-1]:
        return [], [], []
    minimal = feasible.copy()
    popcount = np.array([bin(v).count("1") for v in range(1 << u)])
    fewest = np.where(feasible, popcount, u + 1)  # smallest feasible superset of S
    for b in range(u):
        has = (full >> b) & 1 == 1
        minimal[has] &= ~feasible[full[has] ^ (1 << b)]
        fewest[~has] = np.minimum(fewest[~has], fewest[full[~has] | (1 << b)])
    need = fewest - popcount

    def topics_of(m: int) -> list[int]:
        return [universe[b] for b in range(u) if (m >> b) & 1]

    family = [topics_of(int(m)) for m in np.nonzero(minimal)[0]]
    every = [topics_of(int(m)) for m in np.nonzero(feasible)[0]] if int(feasible.sum()) <= 4096 else []
    keep = need > 0
    for b in range(u):  # a cut is dominated by the one of S + {b} when that needs as many topics
        has = (full >> b) & 1 == 1
        keep[~has] &= need[full[~has] | (1 << b)] < need[~has]
    order = sorted(np.nonzero(keep)[0], key=lambda m: (-need[m], popcount[m]))
    cuts = [([universe[b] for b in range(u) if not (m >> b) & 1], int(need[m])) for m in order]
    return every, family, cuts


def _spread_bounds(cl: _Classes, cap: list[float], by: str) -> list[tuple[int, int]]:
    """Lower bounds on how many units a topic-set group (or a topic's readers) must be spread over.

    If the monitors of a group cannot all fit on one unit, some other unit hosts one of them and receives
    the group's topics: Σ_j z[g,j] >= L_g, where L_g is the fewest units whose capacities could hold every
    member (each unit counted for the most members it could host alone). These cuts are valid for every
    integer allocation and close most of the LP gap when a publishing unit is overloaded.
    """
    if by == "group":
        sets: dict[int, list[int]] = {}
        for c, g in enumerate(cl.group):
            sets.setdefault(g, []).append(c)
    else:
        sets = {}
        for c, g in enumerate(cl.group):
            for k in cl.group_topics[g]:
                sets.setdefault(k, []).append(c)
    out = []
    for key, classes in sets.items():
        sizes = np.array([len(cl.members[c]) for c in classes])
        total = int(sizes.sum())
        hosts = []
        for j, capacity in enumerate(cap):
            per = np.repeat(cl.cpu[classes, j], sizes)
            per.sort()
            hosts.append(int(np.searchsorted(np.cumsum(per), capacity + 1e-9, side="right")))
        hosts.sort(reverse=True)
        covered, need = 0, 0
        for h in hosts:
            if covered >= total:
                break
            covered += h
            need += 1
        if need >= 2:
            out.append((key, need))
    return out


# HiGHS settings measured on benchmarks/milp_scaling.py: a small cut pool keeps the root's separation
# rounds short (one heterogeneous robot block: 3.0 s -> 0.9 s; the heterogeneous 1000 x 20 fleet 4.2 s -> 2.1 s).
HIGHS_OPTIONS: dict[str, Any] = {"mip_pool_soft_limit": 100}

# Largest host family written as an extended formulation (else the m(S) cuts).
HOST_SETS = 512


@dataclass
class _Solved:
    status: str  # "optimal", "time_limit", "infeasible", "error"
    x: np.ndarray | None
    gap: float
    message: str
    bound: float = -math.inf  # HiGHS's final dual bound (a lower bound on the model's objective)
    root_bound: float = -math.inf  # the dual bound after the root node (LP relaxation + cuts)
    nodes: int = 0


def _solve(
    model: _Model, start: np.ndarray | None, time_limit: float, gap: float, work_limit: int | None = None
) -> _Solved:
    """Solve with HiGHS (highspy), passing ``start`` as the incumbent when it is a feasible allocation.

    ``work_limit`` caps the branch-and-bound nodes (``mip_max_nodes``): with one thread and HiGHS's fixed
    random seed the search is deterministic, so a budget in nodes gives the same allocation whatever the
    machine's load, where a wall-clock limit stops at a different point on every run."""
    h = highspy.Highs()
    h.setOptionValue("output_flag", False)
    if math.isfinite(time_limit):
        h.setOptionValue("time_limit", float(time_limit))
    if work_limit is not None:
        h.setOptionValue("mip_max_nodes", int(work_limit))
        h.setOptionValue("random_seed", 0)
    if model.epsilon > 0:
        # A relative gap lets HiGHS stop at an incumbent up to gap x objective above the optimum, which on
        # objectives above epsilon / gap (10 at the defaults) exceeds one migration's penalty: an unchanged
        # optimal input then came back with needless migrations (2 of 124 random inputs, issue 27). An
        # absolute gap of epsilon / 2 and no relative stop leave no room for even one needless migration.
        h.setOptionValue("mip_abs_gap", model.epsilon / 2)
        h.setOptionValue("mip_rel_gap", 0.0)
    else:
        h.setOptionValue("mip_rel_gap", float(gap))
    h.setOptionValue("threads", 1)
    for name, value in HIGHS_OPTIONS.items():
        h.setOptionValue(name, value)
    lp = highspy.HighsLp()
    a = model.a.tocsc()
    lp.num_col_, lp.num_row_ = a.shape[1], a.shape[0]
    lp.col_cost_ = model.c
    lp.col_lower_ = np.zeros(a.shape[1])
    lp.col_upper_ = model.ub
    lp.row_lower_ = model.lo
    lp.row_upper_ = model.hi
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_ = a.indptr
    lp.a_matrix_.index_ = a.indices
    lp.a_matrix_.value_ = a.data
    lp.integrality_ = [
        highspy.HighsVarType.kInteger if v else highspy.HighsVarType.kContinuous for v in model.integrality
    ]
    h.passModel(lp)
    root = [-math.inf]

    def watch(_kind: Any, _message: Any, out: Any, _inp: Any, _data: Any) -> None:
        if out.mip_node_count == 0 and math.isfinite(out.mip_dual_bound):  # still at the root
            root[0] = max(root[0], float(out.mip_dual_bound))

    h.setCallback(watch, None)
    h.startCallback(highspy.cb.HighsCallbackType.kCallbackMipInterrupt)
    if start is not None:
        sol = highspy.HighsSolution()
        sol.col_value = list(start)
        sol.value_valid = True
        h.setSolution(sol)
    h.run()
    status = h.getModelStatus()
    info = h.getInfo()
    has_x = info.primal_solution_status == 2  # kSolutionStatusFeasible
    x = np.array(h.getSolution().col_value) if has_x else None
    # no finite gap yet (stopped before the root bound): report 1.0, "nothing proven", never 0
    gap_value = (float(info.mip_gap) if math.isfinite(info.mip_gap) else 1.0) if has_x else 0.0
    bound = float(info.mip_dual_bound) if math.isfinite(info.mip_dual_bound) else -math.inf
    extra: dict[str, Any] = {
        "bound": bound,
        "root_bound": root[0] if math.isfinite(root[0]) or info.mip_node_count > 1 else bound,
        "nodes": int(info.mip_node_count),
    }
    if status == highspy.HighsModelStatus.kOptimal:
        return _Solved("optimal", x, gap_value, "optimal", **extra)
    if status == highspy.HighsModelStatus.kInfeasible:
        return _Solved("infeasible", None, 0.0, "infeasible", **extra)
    if status in (highspy.HighsModelStatus.kTimeLimit, highspy.HighsModelStatus.kInterrupt) or has_x:
        return _Solved("time_limit", x, gap_value, h.modelStatusToString(status), **extra)
    return _Solved("error", None, 0.0, h.modelStatusToString(status), **extra)


#: The work budget the API, the jobs and the command give a solve by default: branch-and-bound nodes per solve,
#: so that the same statistics give the same allocation on a loaded machine as on an idle one.
DEFAULT_WORK_LIMIT = 2000


def allocate(
    stats: MonitorStats | Mapping,
    *,
    epsilon: float = 1e-3,
    literal_topic_coupling: bool = False,
    observed: Mapping[tuple[str, str], float] | None = None,
    time_limit: float = 10.0,
    mip_rel_gap: float = 1e-4,
    max_candidates: int | None = None,
    decompose: bool = True,
    work_limit: int | None = None,
    formulation: str = "covers",
) -> Allocation:
    """Solve Eqs. 3.21-3.22 for one set of statistics; fall back to the minimum-overload allocation.

    ``mip_rel_gap`` is HiGHS's optimality tolerance (its default, 0.01 %) when ``epsilon`` is 0; with a
    migration penalty the solves stop at an absolute gap of ``epsilon / 2`` instead, so that a solve never
    stops at an allocation with a needless migration (an unchanged optimal input never migrates). A greedy
    allocation is handed to the solver as its first incumbent; when the solver stops at ``time_limit`` seconds the best
    allocation found so far is returned with ``status="time_limit"`` and the remaining relative ``gap``.

    ``max_candidates`` (default None: every unit) is a size reduction for large fleets, not part of the
    thesis: each monitor may then only go to its current unit or to one of the ``max_candidates`` units
    where its topics arrive soonest, and "optimal" means optimal over those candidates.

    ``work_limit`` is a budget in work instead: at most that many branch-and-bound nodes per solve, the
    same allocation on a loaded machine as on an idle one (reproducible simulations). ``status`` is then
    ``"time_limit"`` when the budget stopped the search (the status names are part of the API). Give
    ``time_limit=math.inf`` with it so that the clock never decides.

    ``formulation`` picks the model, all with the same optimum (kept selectable so that
    benchmarks/milp_scaling.py can compare them side by side): ``"textbook"`` is Eqs. 3.21-3.22 as
    written (one x[i,j] per monitor, no cuts, no decomposition); ``"classes"`` the class counts, blocks,
    spread cuts and relief covers; ``"covers"`` (default) adds the host covers (:func:`_host_covers`).
    """
    if formulation not in FORMULATIONS:
        raise InputError(
            f"formulation must be one of {', '.join(FORMULATIONS)}, not {formulation!r}", field="formulation"
        )
    if not isinstance(stats, MonitorStats):
        stats = MonitorStats.from_dict(stats)
    started = time.perf_counter()
    cpu = complete_cpu(stats, observed)
    lit = literal_topic_coupling
    if not stats.monitors:
        return _result(stats, cpu, {}, True, "optimal", 0.0, started, lit)

    def left() -> float:  # every solve shares one time budget
        return max(0.05, time_limit - (time.perf_counter() - started))

    textbook = formulation == "textbook"
    cl = _classes(stats, cpu, lit, merge=not textbook)
    if decompose and not lit and not textbook:
        diag: dict = {}
        split = _decomposed(stats, cpu, cl, epsilon, max_candidates, left, mip_rel_gap, work_limit, formulation, diag)
        if split is not None and split[0] != "infeasible":
            status, gap, placement, blocks = split
            result = _result(stats, cpu, placement, True, status, gap, started, lit)
            result.blocks = blocks
            return _noted(result, diag.get("total"))
    if max_candidates is not None:
        cl.allowed = _candidates(stats, cl, max_candidates)
    search = len(cl.members) * len(stats.nodes) > SEED_SEARCH_PAIRS
    greedy, fits = _greedy(stats, cl, epsilon if formulation == "covers" else None, partition=search)
    if fits and formulation == "covers" and _at_lower_bound(stats, cl, greedy, epsilon):
        return _result(stats, cpu, greedy, True, "optimal", 0.0, started, lit)
    if fits and formulation == "covers" and cl.allowed is None and search:
        # at most half of the time left, so that the whole model still gets to its root bound
        greedy = _neighbourhood(stats, cl, greedy, epsilon, lambda: left() / 2, mip_rel_gap)
    model = _build(stats, cl, epsilon, slack=False, formulation=formulation)
    res = _solve(model, _vector(model, stats, cl, greedy) if fits else None, left(), mip_rel_gap, work_limit)
    if res.x is not None:
        placement, gap = _polished(model, stats, cl, res, epsilon if formulation == "covers" else None)
        return _noted(_result(stats, cpu, placement, True, res.status, gap, started, lit), res)
    if res.status == "error":
        raise InputError(f"the allocation MILP failed: {res.message}")
    # Infeasible, or no allocation found in time: minimise the total excess first, then the delay among
    # minimum-excess allocations (the slack model always has a solution: the greedy one).
    phase1 = _build(stats, cl, 0.0, slack=True, delay_weight=0.0)
    r1 = _solve(phase1, _vector(phase1, stats, cl, greedy), left(), mip_rel_gap, work_limit)
    if r1.x is None:
        return _result(stats, cpu, greedy, fits, "time_limit", 1.0, started, lit)
    excess = float(r1.x[phase1.s0 : phase1.w0].sum())
    phase2 = _build(stats, cl, epsilon, slack=True, max_excess=excess * (1 + 1e-7) + 1e-7)
    r2 = _solve(phase2, r1.x, left(), mip_rel_gap, work_limit)
    best = r2 if r2.x is not None else r1
    placement = _placement(stats, cl, r2.x if r2.x is not None else r1.x)
    if excess <= 1e-7:  # the first solve only ran out of time: this allocation fits
        return _result(stats, cpu, placement, True, "time_limit", best.gap, started, lit)
    proven = res.status == "infeasible" or r1.status == "optimal"
    return _result(stats, cpu, placement, False, "overloaded" if proven else "time_limit", best.gap, started, lit)


# Branch-and-bound nodes of the neighbourhood solve (:func:`_neighbourhood`): its root node (LP, cuts and
# HiGHS's heuristics) did the work on the cross-robot fleets of benchmarks/milp_scaling.py (500 x 10:
# 621 -> 545 after the root, 544 after 50 nodes), so one node keeps it cheap and independent of the clock.
NEIGHBOURHOOD_NODES = 1
# The robot-level seed (:func:`_partition`) and the neighbourhood step run only on models with more (class,
# unit) pairs than this: below it HiGHS solves the whole model in a few ms, and the searches cost more than they
# save (thesis case study 1, 5 classes x 3 units: 8 -> 17 ms per overloaded period with them; case study 2,
# ~190 classes x 3 units, is faster with them).
SEED_SEARCH_PAIRS = 100


def _neighbourhood(
    stats: MonitorStats,
    cl: _Classes,
    seed: dict[str, str],
    epsilon: float,
    left: Callable[[], float],
    gap: float,
) -> dict[str, str]:
    """Improve ``seed`` by solving the MILP restricted to its neighbourhood (a large-neighbourhood step):
    each monitor may only go to its current unit or to a unit where the seed put a monitor of the same
    current unit. That keeps :func:`_partition`'s robot -> host choices and lets HiGHS decide exactly which
    monitors go and which topics each host receives, in a model a few times smaller than the whole one.
    Returns the better of the two (the whole MILP still decides; this is only its first incumbent)."""
    node_ix = {j: b for b, j in enumerate(stats.nodes)}
    hosts: dict[int | None, set[int]] = {}
    for c, members in enumerate(cl.members):
        for a in members:
            hosts.setdefault(cl.current[c], set()).add(node_ix[seed[stats.monitors[a]]])
    allowed = np.zeros((len(cl.members), len(stats.nodes)), dtype=bool)
    for c in range(len(cl.members)):
        allowed[c, sorted(hosts[cl.current[c]])] = True
        if cl.current[c] is not None:
            allowed[c, cl.current[c]] = True
    if allowed.all():
        return seed
    sub = replace(cl, allowed=allowed)
    model = _build(stats, sub, epsilon, slack=False)
    res = _solve(model, _vector(model, stats, sub, seed), left(), gap, NEIGHBOURHOOD_NODES)
    if res.x is None:
        return seed
    found = _placement(stats, sub, res.x)
    delay, _ = _topic_matrices(stats)
    if _cost(stats, cl, found, delay, epsilon) < _cost(stats, cl, seed, delay, epsilon) - 1e-9:
        return found
    return seed


def _polished(
    model: _Model, stats: MonitorStats, cl: _Classes, res: _Solved, epsilon: float | None
) -> tuple[dict[str, str], float]:
    """The solver's allocation and gap; when the budget stopped it (and ``epsilon`` is given), first
    improved by the local search of :func:`_improve`, the gap then recomputed against HiGHS's bound."""
    assert res.x is not None
    placement = _placement(stats, cl, res.x)
    if res.status != "time_limit" or epsilon is None:
        return placement, res.gap
    delay, tcpu = _topic_matrices(stats)
    better = _improve(stats, cl, placement, delay, tcpu, epsilon)
    before = float(model.c @ _vector(model, stats, cl, placement))
    after = float(model.c @ _vector(model, stats, cl, better))
    if after >= before - 1e-9:
        return placement, res.gap
    if not math.isfinite(res.bound):
        return better, res.gap
    return better, max(0.0, (after - res.bound) / max(abs(after), 1e-9))


def _noted(result: Allocation, res: _Solved | None) -> Allocation:
    if res is not None:
        result.root_bound, result.bound, result.nodes = res.root_bound, res.bound, res.nodes
    return result


# ===================================================================================================
# Decomposition into independent blocks
# ===================================================================================================


def _blocks(cl: _Classes) -> list[list[int]]:
    """Monitor indices grouped so that no two groups share a topic or a current unit (union-find)."""
    parent = list(range(len(cl.members)))

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    first: dict[tuple, int] = {}
    for c in range(len(cl.members)):
        keys: list[tuple[str, int]] = [("t", k) for k in cl.group_topics[cl.group[c]]]
        unit = cl.current[c]
        if unit is not None:
            keys.append(("u", unit))
        for key in keys:
            if key in first:
                parent[find(c)] = find(first[key])
            else:
                first[key] = c
    out: dict[int, list[int]] = {}
    for c, members in enumerate(cl.members):
        out.setdefault(find(c), []).extend(members)
    return [sorted(m) for m in out.values()]


def _substats(stats: MonitorStats, monitors: list[int]) -> MonitorStats:
    names = [stats.monitors[a] for a in monitors]
    used = {k for i in names for k in stats.monitor_topics[i]}
    topics = [k for k in stats.topics if k in used]
    return MonitorStats(
        stats.nodes,
        stats.available,
        stats.threshold,
        stats.speed,
        topics,
        {k: stats.delay[k] for k in topics},
        {k: stats.topic_cpu[k] for k in topics},
        names,
        {i: stats.monitor_topics[i] for i in names},
        {i: stats.monitor_cpu[i] for i in names},
        {i: stats.current[i] for i in names},
        {i: stats.tolerant.get(i, False) for i in names},
        {i: stats.active_instances.get(i, 0) for i in names},
    )


def _loads(stats: MonitorStats, cpu: np.ndarray, placement: Mapping[str, str]) -> dict[str, float]:
    node_ix = {j: b for b, j in enumerate(stats.nodes)}
    share = dict.fromkeys(stats.nodes, 0.0)
    received: set[tuple[str, str]] = set()
    for a, i in enumerate(stats.monitors):
        j = placement[i]
        share[j] += float(cpu[a, node_ix[j]])
        received.update((k, j) for k in stats.monitor_topics[i])
    for k, j in received:
        share[j] += stats.topic_cpu[k].get(j, 0.0)
    return share


def _decomposed(
    stats: MonitorStats,
    cpu: np.ndarray,
    cl: _Classes,
    epsilon: float,
    max_candidates: int | None,
    left: Callable[[], float],
    gap: float,
    work_limit: int | None = None,
    formulation: str = "covers",
    diag: dict | None = None,
) -> tuple[str, float, dict[str, str], int] | None:
    """Solve independent blocks separately; exact, or None to fall back to the whole model.

    Monitors that share no topic and no current unit interact only through the units' capacities. Each
    block is solved with every unit's full capacity: that is a relaxation (the delay objective and the
    ε term are sums over blocks, since no topic is read in two blocks), so the sum of the blocks' optima
    is a lower bound, and when the blocks' allocations together respect every capacity their union is
    optimal. When they do not, the blocks that share an overloaded unit are merged and solved again,
    until the union fits (in the worst case everything is one block: the whole model). Returns
    ("infeasible", ...) when a block alone cannot fit (then nothing can), None when time runs out.
    """
    parts = _blocks(cl)
    if len(parts) < 2:
        return None
    diag = {} if diag is None else diag
    solved: dict[tuple[int, ...], tuple[str, float, dict[str, str]]] = {}
    cap = stats.capacity()
    while True:
        for part in parts:
            key = tuple(part)
            if key in solved:
                continue
            sub = _substats(stats, part)
            sub_cpu = cpu[part]
            sub_cl = _classes(sub, sub_cpu, False)
            if max_candidates is not None:
                sub_cl.allowed = _candidates(sub, sub_cl, max_candidates)
            greedy, fits = _greedy(sub, sub_cl, epsilon if formulation == "covers" else None)
            model = _build(sub, sub_cl, epsilon, slack=False, formulation=formulation)
            res = _solve(model, _vector(model, sub, sub_cl, greedy) if fits else None, left(), gap, work_limit)
            if res.status == "infeasible":
                return "infeasible", 0.0, {}, 0
            if res.x is None:
                return None
            polish = epsilon if formulation == "covers" else None
            solved[key] = (res.status, *_polished(model, sub, sub_cl, res, polish)[::-1])
            diag[key] = res
        placement: dict[str, str] = {}
        for part in parts:
            placement.update(solved[tuple(part)][2])
        share = _loads(stats, cpu, placement)
        over = [j for j in stats.nodes if share[j] > cap[j] + 1e-6]
        # blocks that place monitors on an overloaded unit are merged (union-find over the parts)
        owner = {stats.monitors[a]: p for p, part in enumerate(parts) for a in part}
        parent = list(range(len(parts)))

        def find(p: int, parent: list[int] = parent) -> int:
            while parent[p] != p:
                p = parent[p]
            return p

        merged = False
        for j in over:
            users = sorted({owner[i] for i, where in placement.items() if where == j})
            for p in users[1:]:
                if find(p) != find(users[0]):
                    parent[find(p)] = find(users[0])
                    merged = True
        if not merged:
            statuses = [solved[tuple(part)] for part in parts]
            final = [diag[tuple(part)] for part in parts]
            diag.clear()
            diag["total"] = _Solved(
                "",
                None,
                0.0,
                "",
                sum(r.bound for r in final),
                sum(r.root_bound for r in final),
                sum(r.nodes for r in final),
            )
            status = "optimal" if all(s[0] == "optimal" for s in statuses) else "time_limit"
            return status, max(s[1] for s in statuses), {i: placement[i] for i in stats.monitors}, len(parts)
        groups: dict[int, list[int]] = {}
        for p, part in enumerate(parts):
            groups.setdefault(find(p), []).extend(part)
        parts = [sorted(g) for g in groups.values()]


def _candidates(stats: MonitorStats, cl: _Classes, k: int) -> np.ndarray:
    if k < 1:
        raise InputError("max_candidates must be >= 1", field="max_candidates")
    delay, _ = _topic_matrices(stats)
    allowed = np.zeros((len(cl.members), len(stats.nodes)), dtype=bool)
    for c in range(len(cl.members)):
        topics = cl.group_topics[cl.group[c]]
        cost = delay[topics].sum(axis=0) if topics else np.zeros(len(stats.nodes))
        allowed[c, np.argsort(cost, kind="stable")[:k]] = True
        if cl.current[c] is not None:
            allowed[c, cl.current[c]] = True
    return allowed


def _greedy(
    stats: MonitorStats, cl: _Classes, improve: float | None = None, partition: bool = True
) -> tuple[dict[str, str], bool]:
    """A quick allocation: keep monitors where they are if everything fits, else place the largest
    monitors first on the unit that adds the least delay among those with room. ``fits`` tells whether
    every capacity holds. With ``improve`` (the ε of the objective), a fitting allocation is then
    improved by local search (:func:`_improve`) and compared with the robot-level seed of
    :func:`_partition` (unless ``partition`` is False)."""
    cap = stats.capacity()
    nodes = stats.nodes
    reads = {a: cl.group_topics[cl.group[c]] for c, members in enumerate(cl.members) for a in members}
    cls_of = {a: c for c, members in enumerate(cl.members) for a in members}
    delay, tcpu = _topic_matrices(stats)

    def attempt(order: list[int], stay: bool) -> tuple[dict[str, str], bool]:
        left = np.array([cap[j] for j in nodes], dtype=float)
        got: list[set[int]] = [set() for _ in nodes]
        out: dict[str, str] = {}
        ok = True
        for a in order:
            c = cls_of[a]
            need = reads[a]
            options = []
            for b in range(len(nodes)):
                if cl.allowed is not None and not cl.allowed[c, b]:
                    continue
                new = [k for k in need if k not in got[b]]
                extra_cpu = cl.cpu[c, b] + sum(tcpu[k, b] for k in new)
                prefer = 0 if stay and cl.current[c] == b else 1
                options.append((prefer, sum(delay[k, b] for k in new), -left[b], b, extra_cpu, new))
            options.sort()
            choice = next((o for o in options if o[4] <= left[o[3]] + 1e-9), None)
            if choice is None:
                ok = False
                choice = max(options, key=lambda o: left[o[3]] - o[4])
            b = choice[3]
            left[b] -= choice[4]
            got[b].update(choice[5])
            out[stats.monitors[a]] = nodes[b]
        return out, ok

    by_size = sorted(range(len(stats.monitors)), key=lambda a: -float(cl.cpu[cls_of[a]].max()))
    repaired = _repair(stats, cl, delay, tcpu)
    if repaired is None:
        repaired, ok = attempt(by_size, stay=True)
        if not ok:
            repaired, ok = attempt(by_size, stay=False)
        if not ok:
            return repaired, False
    if improve is not None:
        repaired = _improve(stats, cl, repaired, delay, tcpu, improve)
        seeded = _partition(stats, cl, delay, tcpu, improve) if partition else None
        if seeded is not None:
            seeded = _improve(stats, cl, seeded, delay, tcpu, improve)
            if _cost(stats, cl, seeded, delay, improve) < _cost(stats, cl, repaired, delay, improve) - 1e-9:
                repaired = seeded
    return repaired, True


def _cost(stats: MonitorStats, cl: _Classes, placement: Mapping[str, str], delay: np.ndarray, epsilon: float) -> float:
    """The objective of a placement: Σ delay over received (topic, unit) pairs + ε per migration."""
    node_ix = {j: b for b, j in enumerate(stats.nodes)}
    received: set[tuple[int, int]] = set()
    moved = 0
    for c, members in enumerate(cl.members):
        for a in members:
            b = node_ix[placement[stats.monitors[a]]]
            received.update((k, b) for k in cl.group_topics[cl.group[c]])
            moved += cl.current[c] is not None and cl.current[c] != b
    return sum(float(delay[k, b]) for k, b in received) + epsilon * moved


def _at_lower_bound(stats: MonitorStats, cl: _Classes, placement: Mapping[str, str], epsilon: float) -> bool:
    """Whether ``placement`` is optimal by the trivial bound: every topic some monitor reads is received on
    at least one unit, at its lowest delay there at best, and no migration costs less than none. A period
    where the monitors fit where they run and their topics arrive soonest there (thesis case study 1 while
    the edge has room) is then answered without a solver."""
    delay, _ = _topic_matrices(stats)
    read = sorted({k for ks in cl.group_topics for k in ks})
    bound = float(delay[read].min(axis=1).sum()) if read else 0.0
    return _cost(stats, cl, placement, delay, epsilon) <= bound + 1e-9


def _improve(
    stats: MonitorStats,
    cl: _Classes,
    placement: Mapping[str, str],
    delay: np.ndarray,
    tcpu: np.ndarray,
    epsilon: float,
    max_passes: int = 20,
) -> dict[str, str]:
    """Local search on a capacity-feasible allocation (a better first incumbent for HiGHS; the optimum
    is unchanged since the MILP still decides). A move takes every monitor on unit a that reads topic k
    (or every monitor of one topic set) to one unit b, when that fits b's capacity and lowers the
    objective: the delays of the topics a no longer needs minus those b starts receiving, plus ε per
    monitor leaving its current unit. Moves are tried in a fixed order, so the result is deterministic."""
    j_count, k_count = len(stats.nodes), len(stats.topics)
    cap = np.array([stats.capacity()[j] for j in stats.nodes])
    node_ix = {j: b for b, j in enumerate(stats.nodes)}
    cls_of = np.zeros(len(stats.monitors), dtype=int)
    for c, members in enumerate(cl.members):
        cls_of[members] = c
    allowed = cl.allowed if cl.allowed is not None else np.ones((len(cl.members), j_count), dtype=bool)
    topics_of = [cl.group_topics[cl.group[c]] for c in cls_of]
    place = np.array([node_ix[placement[i]] for i in stats.monitors])
    readers = np.zeros((k_count, j_count), dtype=int)
    load = np.zeros(j_count)
    for a, b in enumerate(place):
        load[b] += cl.cpu[cls_of[a], b]
        for k in topics_of[a]:
            readers[k, b] += 1
    load += (tcpu * (readers > 0)).sum(axis=0)
    current = np.array([-1 if cl.current[c] is None else cl.current[c] for c in cls_of])

    cpu_of = cl.cpu[cls_of]  # monitor x unit

    def try_move(movers: list[int], a: int) -> bool:
        count: dict[int, int] = {}
        for m in movers:
            for k in topics_of[m]:
                count[k] = count.get(k, 0) + 1
        ks = np.fromiter(count, dtype=int, count=len(count))
        freed = ks[readers[ks, a] == np.fromiter(count.values(), dtype=int, count=len(count))]
        here = np.bincount(current[movers][current[movers] >= 0], minlength=j_count)
        saved = float(delay[freed, a].sum()) + epsilon * here[a]
        new = readers[ks] == 0  # topic x unit: not received there yet
        gain = saved - (delay[ks] * new).sum(axis=0) - epsilon * here
        extra = cpu_of[movers].sum(axis=0) + (tcpu[ks] * new).sum(axis=0)
        ok = (gain > 1e-9) & (load + extra <= cap + 1e-9) & allowed[cls_of[movers]].all(axis=0)
        ok[a] = False
        if not ok.any():
            return False
        b = int(np.argmax(np.where(ok, gain, -np.inf)))
        load[b] += extra[b]
        load[a] -= float(cpu_of[movers, a].sum()) + float(tcpu[freed, a].sum())
        place[movers] = b
        for m in movers:
            for k in topics_of[m]:
                readers[k, a] -= 1
                readers[k, b] += 1
        return True

    for _ in range(max_passes):
        moved = False
        for a in range(j_count):
            for k in np.nonzero(readers[:, a])[0]:
                movers = [int(m) for m in np.nonzero(place == a)[0] if k in topics_of[m]]
                if movers and try_move(movers, a):
                    moved = True
            by_group: dict[int, list[int]] = {}
            for m in np.nonzero(place == a)[0]:
                by_group.setdefault(cl.group[cls_of[m]], []).append(int(m))
            for movers in by_group.values():
                if all(place[m] == a for m in movers) and try_move(movers, a):
                    moved = True
        if not moved:
            break
    return {i: stats.nodes[place[a]] for a, i in enumerate(stats.monitors)}


class _Plan:
    """A placement with exact incremental bookkeeping: receivers per (unit, topic), monitor CPU per unit.
    The objective and the capacity check of any candidate are then a few array operations, so that the
    robot-level search of :func:`_partition` can evaluate every candidate exactly instead of estimating."""

    def __init__(
        self, stats: MonitorStats, cl: _Classes, delay: np.ndarray, tcpu: np.ndarray, epsilon: float, place: np.ndarray
    ):
        j_count, k_count = len(stats.nodes), len(stats.topics)
        self.cls_of = np.zeros(len(stats.monitors), dtype=int)
        for c, members in enumerate(cl.members):
            self.cls_of[members] = c
        self.cpu = cl.cpu[self.cls_of]  # monitor x unit
        self.reads = np.zeros((len(stats.monitors), k_count))  # monitor x topic incidence
        for a, c in enumerate(self.cls_of):
            self.reads[a, cl.group_topics[cl.group[c]]] = 1
        self.group = np.array([cl.group[c] for c in self.cls_of], dtype=int)
        self.allowed = (cl.allowed if cl.allowed is not None else np.ones((len(cl.members), j_count), dtype=bool))[
            self.cls_of
        ]
        self.current = np.array([-1 if cl.current[c] is None else cl.current[c] for c in self.cls_of])
        self.cap = np.array([stats.capacity()[j] for j in stats.nodes])
        self.delay_t, self.tcpu_t = delay.T.copy(), tcpu.T.copy()  # unit x topic
        self.epsilon = epsilon
        self.place = place.copy()
        self.readers = np.zeros((j_count, k_count))  # unit x topic
        np.add.at(self.readers, self.place, self.reads)
        self.load = np.bincount(self.place, weights=self.cpu[np.arange(len(place)), self.place], minlength=j_count)

    def copy(self) -> _Plan:
        other = object.__new__(_Plan)
        other.__dict__.update(self.__dict__)
        other.place, other.readers, other.load = self.place.copy(), self.readers.copy(), self.load.copy()
        return other

    def totals(self) -> np.ndarray:
        return self.load + (self.tcpu_t * (self.readers > 0)).sum(axis=1)

    def objective(self) -> float:
        moved = int(((self.place != self.current) & (self.current >= 0)).sum())
        return float((self.delay_t * (self.readers > 0)).sum()) + self.epsilon * moved

    def move(self, monitors: np.ndarray, b: int) -> None:
        if not len(monitors):
            return
        src = self.place[monitors]
        np.add.at(self.readers, src, -self.reads[monitors])
        self.readers[b] += self.reads[monitors].sum(axis=0)
        np.subtract.at(self.load, src, self.cpu[monitors, src])
        self.load[b] += float(self.cpu[monitors, b].sum())
        self.place[monitors] = b

    def shed(self, r: int, h: int) -> float:
        """Move monitors from overloaded unit r to unit h, one topic set at a time, cheapest added delay
        (minus the delay r stops paying) per CPU freed first, while h has room; returns r's remaining
        excess. Whole topic sets go together so that h receives each topic once."""
        while True:
            total = self.totals()
            over = total[r] - self.cap[r]
            if over <= 1e-9:
                return 0.0
            on = np.nonzero((self.place == r) & self.allowed[:, h])[0]
            if not len(on):
                return over
            groups, first, inv = np.unique(self.group[on], return_index=True, return_inverse=True)
            g_reads = self.reads[on[first]]  # group x topic
            size = np.bincount(inv, minlength=len(groups)).astype(float)
            added = g_reads @ (self.delay_t[h] * (self.readers[h] == 0))
            added_cpu = g_reads @ (self.tcpu_t[h] * (self.readers[h] == 0))
            alone = g_reads * (self.readers[r] == size[:, None])  # topics only this group reads on r
            saved = alone @ self.delay_t[r]
            freed = np.bincount(inv, weights=self.cpu[on, r], minlength=len(groups)) + alone @ self.tcpu_t[r]
            room = self.cap[h] - total[h] - added_cpu
            smallest = np.full(len(groups), np.inf)
            np.minimum.at(smallest, inv, self.cpu[on, h])
            fits = room >= smallest - 1e-9  # at least one member fits
            if not fits.any():
                return over
            score = np.where(fits, (added - saved + 1e-6) / np.maximum(freed, 1e-9), np.inf)
            g = int(np.argmin(score))
            members = on[inv == g]
            members = members[np.argsort(-self.cpu[members, r], kind="stable")]
            take, used, got = [], 0.0, 0.0
            for m in members:  # largest first; one that does not fit is skipped, a smaller one may
                if used + self.cpu[m, h] > room[g] + 1e-9:
                    continue
                take.append(int(m))
                used += self.cpu[m, h]
                got += self.cpu[m, r]
                if got >= over - 1e-9:
                    break
            self.move(np.array(take, dtype=int), h)

    def relieve(self, r: int, first: int | None, order: list[int]) -> bool:
        """Shed r's excess to ``first``, then to the units of ``order`` in turn; True when r fits."""
        hosts = ([first] if first is not None else []) + [h for h in order if h != first]
        for h in hosts:
            if h != r and self.shed(r, h) <= 1e-9:
                return True
        return self.totals()[r] <= self.cap[r] + 1e-9


def _partition(
    stats: MonitorStats, cl: _Classes, delay: np.ndarray, tcpu: np.ndarray, epsilon: float, max_passes: int = 8
) -> dict[str, str] | None:
    """Robot-level allocation for fleets whose units cannot keep their monitors: decide, for each
    overloaded unit r, which unit hosts its overflow (kept together, so that the host receives r's topics
    once), then search over those choices: move one unit's overflow to another host, move every monitor
    still at home on a unit to one host, or swap the hosts of two overloaded units (cross reads make two
    units' monitors cheaper on the same host). Every
    candidate is evaluated exactly (:class:`_Plan`): the delay is the sum over received (topic, unit)
    pairs and a candidate is kept only when every capacity holds. The integer problem is partition-like
    (which intermediate unit hosts which robots) and the per-monitor moves of :func:`_improve` cannot
    cross its valleys; this one does. Deterministic: fixed orders, ties by index. None when some unit
    cannot be relieved."""
    j_count = len(stats.nodes)
    # every monitor starts on its current unit (as in _repair: else its first allowed unit)
    origin = np.zeros(len(stats.monitors), dtype=int)
    for c, members in enumerate(cl.members):
        cur = cl.current[c]
        if cur is None or (cl.allowed is not None and not cl.allowed[c, cur]):
            cur = int(np.argmax(cl.allowed[c])) if cl.allowed is not None else 0
        origin[members] = cur
    plan = _Plan(stats, cl, delay, tcpu, epsilon, origin)
    excess = plan.totals() - plan.cap
    over = [int(r) for r in np.argsort(-excess, kind="stable") if excess[r] > 1e-9]
    if not over:
        return None
    # fallback hosts when the chosen one fills up: least total delay of the unit's topics first (a static
    # order keeps the search deterministic and cheap)

    def fallback(r: int) -> list[int]:
        topics = plan.reads[origin == r].any(axis=0)
        cost = plan.delay_t[:, topics].sum(axis=1)
        return [int(h) for h in np.lexsort((np.arange(j_count), cost)) if h != r]

    orders = {r: fallback(r) for r in over}

    def replan(base: _Plan, moves: list[tuple[int, int]]) -> _Plan | None:
        trial = base.copy()
        for r, _ in moves:  # every monitor of these units comes home first
            back = np.nonzero((origin == r) & (trial.place != r))[0]
            trial.move(back, r)
        for r, h in moves:
            if not trial.relieve(r, h, orders[r]):
                return None
        if np.any(trial.totals() > trial.cap + 1e-9):
            return None
        return trial

    for r in over:  # construction: each overloaded unit in turn (largest excess first) takes its best host
        best: tuple[float, int, _Plan] | None = None
        for h in orders[r]:
            trial = plan.copy()
            if not trial.relieve(r, h, orders[r]) and trial.totals()[r] > trial.cap[r] + 1e-9:
                continue
            value = trial.objective()
            if best is None or value < best[0] - 1e-9:
                best = (value, h, trial)
        if best is None:
            return None
        plan = best[2]
    if np.any(plan.totals() > plan.cap + 1e-9):
        return None

    def host(r: int) -> int:  # where most of r's overflow sits
        away = plan.place[(origin == r) & (plan.place != r)]
        return int(np.bincount(away, minlength=j_count).argmax()) if len(away) else r

    value = plan.objective()
    homes = sorted({int(r) for r in origin})
    for _ in range(max_passes):
        improved = False
        for r in over:  # move one unit's overflow to another host
            for h in orders[r]:
                if h == host(r):
                    continue
                found = replan(plan, [(r, h)])
                if found is not None and found.objective() < value - 1e-9:
                    plan, value, improved = found, found.objective(), True
        for r in homes:  # move every monitor still at home on r: cross reads favour whole robots on one
            at_home = np.nonzero((origin == r) & (plan.place == r))[0]  # host (their foreign topics arrive
            for h in range(j_count):  # there once for all of them)
                if h == r or not len(at_home) or not plan.allowed[at_home, h].all():
                    continue
                trial = plan.copy()
                trial.move(at_home, h)
                if np.all(trial.totals() <= trial.cap + 1e-9) and trial.objective() < value - 1e-9:
                    plan, value, improved = trial, trial.objective(), True
                    at_home = np.nonzero((origin == r) & (plan.place == r))[0]
        for x, r1 in enumerate(over):  # swap the hosts of two units
            for r2 in over[x + 1 :]:
                h1, h2 = host(r1), host(r2)
                if h1 in (h2, r2) or h2 == r1:
                    continue
                for moves in ([(r1, h2), (r2, h1)], [(r2, h1), (r1, h2)]):
                    found = replan(plan, moves)
                    if found is not None and found.objective() < value - 1e-9:
                        plan, value, improved = found, found.objective(), True
                        break
        if not improved:
            break
    return {i: stats.nodes[plan.place[a]] for a, i in enumerate(stats.monitors)}


def _repair(stats: MonitorStats, cl: _Classes, delay: np.ndarray, tcpu: np.ndarray) -> dict[str, str] | None:
    """Start from the current allocation and relieve overloaded units by moving monitors of one topic set
    at a time to the unit where that costs the least added delay per unit of CPU freed (a set-union
    knapsack heuristic). None when it gets stuck."""
    nodes, j_count = stats.nodes, len(stats.nodes)
    cap = np.array([stats.capacity()[j] for j in nodes])
    cls_of = [0] * len(stats.monitors)
    for c, members in enumerate(cl.members):
        for a in members:
            cls_of[a] = c
    allowed = cl.allowed if cl.allowed is not None else np.ones((len(cl.members), j_count), dtype=bool)
    place = []
    for a in range(len(stats.monitors)):
        c = cls_of[a]
        cur = cl.current[c]
        if cur is None or not allowed[c, cur]:
            cur = int(np.argmax(allowed[c]))
        place.append(cur)
    readers = np.zeros((len(stats.topics), j_count), dtype=int)
    load = np.zeros(j_count)
    for a, b in enumerate(place):
        c = cls_of[a]
        load[b] += cl.cpu[c, b]
        for k in cl.group_topics[cl.group[c]]:
            readers[k, b] += 1

    def total(b: int) -> float:
        return load[b] + float(tcpu[readers[:, b] > 0, b].sum())

    for _ in range(4 * len(stats.monitors) + 10):
        over = [(total(b) - cap[b], b) for b in range(j_count) if total(b) > cap[b] + 1e-9]
        if not over:
            return {stats.monitors[a]: nodes[b] for a, b in enumerate(place)}
        excess, b = max(over)
        on_b: dict[int, list[int]] = {}
        for a, pb in enumerate(place):
            if pb == b:
                on_b.setdefault(cl.group[cls_of[a]], []).append(a)
        best = None
        for g, members in on_b.items():
            members.sort(key=lambda a: -cl.cpu[cls_of[a], b])
            topics = cl.group_topics[g]
            for d in range(j_count):
                if d == b:
                    continue
                new = [k for k in topics if readers[k, d] == 0]
                room = cap[d] - total(d) - float(tcpu[new, d].sum())
                moved, freed, used = [], 0.0, 0.0
                for a in members:
                    c = cls_of[a]
                    if not allowed[c, d] or used + cl.cpu[c, d] > room + 1e-9:
                        continue
                    moved.append(a)
                    freed += cl.cpu[c, b]
                    used += cl.cpu[c, d]
                    if freed >= excess - 1e-9:
                        break
                if moved and freed > 0:
                    score = (float(delay[new, d].sum()) + 1e-6) / freed
                    if best is None or score < best[0]:
                        best = (score, d, moved)
        if best is None:
            return None
        _, d, moved = best
        for a in moved:
            c = cls_of[a]
            place[a] = d
            load[b] -= cl.cpu[c, b]
            load[d] += cl.cpu[c, d]
            for k in cl.group_topics[cl.group[c]]:
                readers[k, b] -= 1
                readers[k, d] += 1
    return None


def _vector(model: _Model, stats: MonitorStats, cl: _Classes, placement: Mapping[str, str]) -> np.ndarray:
    """The model's variable vector for a placement (used as the solver's starting incumbent)."""
    j_count = len(stats.nodes)
    node_ix = {j: b for b, j in enumerate(stats.nodes)}
    x = np.zeros(len(model.c))
    cls_of = {a: c for c, members in enumerate(cl.members) for a in members}
    load = np.zeros(j_count)
    for a, i in enumerate(stats.monitors):
        c, b = cls_of[a], node_ix[placement[i]]
        x[c * j_count + b] += 1
        x[model.z0 + cl.group[c] * j_count + b] = 1
        load[b] += cl.cpu[c, b]
    for g, topics in enumerate(cl.group_topics):
        for b in range(j_count):
            if x[model.z0 + g * j_count + b]:
                for k in topics:
                    x[model.y0 + k * j_count + b] = 1
    _, tcpu = _topic_matrices(stats)
    for b in range(j_count):
        load[b] += sum(tcpu[k, b] for k in range(len(stats.topics)) if x[model.y0 + k * j_count + b])
    if model.s0 < model.w0:
        cap = stats.capacity()
        x[model.s0 : model.w0] = np.maximum(0.0, load - np.array([cap[j] for j in stats.nodes]))
    for fam in model.families:
        elsewhere = {
            k
            for k in range(len(stats.topics))
            for b in range(j_count)
            if (b == fam.unit if fam.host else b != fam.unit) and x[model.y0 + k * j_count + b]
        }
        if fam.complete:
            chosen = next((o for o, topics in enumerate(fam.sets) if set(topics) == elsewhere & fam.universe), None)
        else:
            chosen = next((o for o, topics in enumerate(fam.sets) if set(topics) <= elsewhere), None)
        if chosen is None:  # the start does not shed enough load (it is not feasible anyway)
            return x
        x[fam.w0 + chosen] = 1
    return x


def _placement(stats: MonitorStats, cl: _Classes, x: np.ndarray) -> dict[str, str]:
    """Monitor -> unit from the class counts (a class's members go first to their current unit)."""
    j_count = len(stats.nodes)
    counts = np.rint(x[: len(cl.members) * j_count]).astype(int).reshape(len(cl.members), j_count)
    out: dict[str, str] = {}
    for c, members in enumerate(cl.members):
        unit = cl.current[c]
        order = ([unit] if unit is not None else []) + [b for b in range(j_count) if b != unit]
        queue = list(members)
        for b in order:
            for _ in range(counts[c, b]):
                if queue:
                    out[stats.monitors[queue.pop(0)]] = stats.nodes[b]
        for a in queue:  # rounding safety: never leave a monitor unplaced
            out[stats.monitors[a]] = stats.nodes[int(np.argmax(counts[c]))]
    return {i: out[i] for i in stats.monitors}


def _result(
    stats: MonitorStats,
    cpu: np.ndarray,
    allocation: dict[str, str],
    feasible: bool,
    status: str,
    gap: float,
    started: float,
    literal: bool,
) -> Allocation:
    node_ix = {j: b for b, j in enumerate(stats.nodes)}
    received: dict[str, set[str]] = {j: set() for j in stats.nodes}
    share = {j: 0.0 for j in stats.nodes}
    for a, i in enumerate(stats.monitors):
        j = allocation[i]
        received[j].update(stats.topics if literal else stats.monitor_topics[i])
        share[j] += float(cpu[a, node_ix[j]])
    objective = 0.0
    for j, topics in received.items():
        for k in topics:
            share[j] += stats.topic_cpu[k].get(j, 0.0)
            objective += stats.delay[k].get(j, 0.0)
    cap = stats.capacity()
    over = {j: round(share[j] - cap[j], 9) for j in stats.nodes if share[j] > cap[j] + 1e-7}
    migrations = [i for i in stats.monitors if stats.current[i] is not None and allocation[i] != stats.current[i]]
    result = Allocation(
        feasible=feasible,
        objective=round(objective, 9),
        allocation=allocation,
        cpu={j: round(v, 9) for j, v in share.items()},
        capacity=cap,
        overloaded=over if not feasible else {},
        migrations=migrations,
        received={j: sorted(t) for j, t in received.items()},
        solve_time_ms=round((time.perf_counter() - started) * 1000, 3),
        status=status,
        gap=gap,
    )
    if not feasible:
        overload_plan(stats, cpu, result)
    return result


def overload_plan(stats: MonitorStats, cpu: np.ndarray, result: Allocation) -> None:
    """The two overload strategies of §11.2 on the overloaded units (fills priorities/drop_events)."""
    node_ix = {j: b for b, j in enumerate(stats.nodes)}
    mon_ix = {i: a for a, i in enumerate(stats.monitors)}
    for j, excess in result.overloaded.items():
        here = [i for i in stats.monitors if result.allocation[i] == j]
        # strategy 1: priority proportional to active instances (lowest when none are active)
        for i in here:
            result.priorities[i] = stats.active_instances.get(i, 0)
        # strategy 2: tolerant monitors drop old events and reset, least urgent first
        remaining = excess
        for i in sorted(here, key=lambda i: (stats.active_instances.get(i, 0), i)):
            if remaining <= 1e-9:
                break
            if stats.tolerant.get(i):
                result.drop_events.append(i)
                remaining -= float(cpu[mon_ix[i], node_ix[j]])
        if remaining > 1e-9:
            result.unresolved[j] = round(remaining, 9)


# ===================================================================================================
# The coordinator's periodic allocator
# ===================================================================================================


class MonitorAllocator:
    """Runs the MILP every period on SMA-filtered statistics and remembers per-unit monitor CPU.

    When the filtered statistics are exactly those of the previous period (a steady system), the previous
    allocation is returned without solving again (``reuse=True``) and nothing migrates: the MILP would find
    the same allocation (or, stopped by the time limit, one no better than the one in place).
    """

    def __init__(self, window: int = 10, reuse: bool = True, **options: Any):
        self.filter = StatsFilter(window)
        self.options = options
        self.observed: dict[tuple[str, str], float] = {}
        self.reuse = reuse
        self._last: tuple[str, Allocation] | None = None

    def step(self, stats: MonitorStats | Mapping) -> Allocation:
        if not isinstance(stats, MonitorStats):
            stats = MonitorStats.from_dict(stats)
        filtered = self.filter.update(stats)
        for i, per_node in filtered.monitor_cpu.items():
            for j, v in per_node.items():
                self.observed[(i, j)] = v
        key = _fingerprint(filtered, self.observed) if self.reuse else ""
        if self.reuse and self._last is not None and self._last[0] == key:
            last = self._last[1]
            return replace(last, migrations=[], solve_time_ms=0.0, reused=True)
        result = allocate(filtered, observed=self.observed, **self.options)
        self._last = (key, result)
        return result


def _fingerprint(stats: MonitorStats, observed: Mapping[tuple[str, str], float]) -> str:
    doc = (
        [(j, round(stats.available[j], 9), stats.threshold[j], stats.speed[j]) for j in stats.nodes],
        [(k, sorted(stats.delay[k].items()), sorted(stats.topic_cpu[k].items())) for k in stats.topics],
        [(i, stats.monitor_topics[i], stats.current[i], stats.tolerant.get(i), stats.active_instances.get(i))
         for i in stats.monitors],
        sorted((i, j, round(v, 9)) for (i, j), v in observed.items()),
    )  # fmt: skip
    return repr(doc)
