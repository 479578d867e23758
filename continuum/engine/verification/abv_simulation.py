"""Simulation of monitor orchestration in the thesis's two ABV case studies (§4.5.1 and §4.5.2, Fig. 4.22
and Fig. 4.24; spec 03 §13 and §14, scenarios S-ABV1 and S-ABV2).

A discrete-time loop with the coordinator's period (1 s). At every period:

1. each unit's *background* CPU (the system under verification, or the testbench) is read from the
   scenario's load profile; the monitors run where the previous allocation put them;
2. the verification CPU of a unit is the CPU of its monitors plus that of receiving their topics from
   other units; a unit that cannot give the verification that much CPU (its physical room, 100 % minus the
   background) is *overloaded*: its tolerant monitors drop old events (overload strategy 2, §11.2) until the
   rest fits, its other monitors fall behind (strategy 1: they keep their accuracy, lose responsiveness);
3. the handlers' statistics (``continuum.monitorstats/v1``: available CPU = 100 % minus the background,
   thresholds, per-monitor CPU where the monitors run, topic delays and reception CPU) go through the
   coordinator's :class:`~continuum.engine.verification.monitor_milp.MonitorAllocator` (SMA filter + the Eq. 3.21-3.22
   MILP); the monitors it moves migrate during the next period (Fig. 3.43), which costs a short CPU spike
   on both units (``migration_cpu`` per monitor moved; the thesis sees such spikes in Fig. 4.24).

Readings and model choices (each a field of :class:`Scenario`; the thesis gives no more detail):

* Events moved by a migration (Fig. 3.43 step 5): the events of the monitor's topics published during the
  hand-over window, ``rate * (2 * link delay + handover_ms)`` (the T0 round trip plus the transfer). A
  model figure, not a measurement; the lossless protocol itself is tested on real monitors in
  tests/engine/verification/test_stl_migration.py and with real processes in tests/verification.
* RB-Kairos makespan of the navigation chain (ORB-SLAM + local planner on the Jetson): spec 03 §13.2's
  linear contention model fitted to the thesis's three points (115 ms without verification, 140 ms with
  201 monitors on the Jetson, 125 ms after 150 of them left):
  ``makespan = 115 + 25/201 · n_jetson + (10 - 51 · 25/201) · [some monitor runs off the Jetson]`` ms.
  The first term is CPU contention: each monitor on the Jetson steals the same share of the cores from
  the navigation chain; the second is the cost of forwarding the navigation topics over the network.
* The robot's mission (§4.5.2): legs from ⟨x1, y1⟩ to ⟨x2, y2⟩; the motor-velocity controller needs an
  update every 125 ms: in a period where the makespan meets it the robot advances, otherwise it heads the
  wrong way (thesis). The navigation assertion
  ``G((robot_x == x1 && robot_y == y1 && newGoal) -> F[0,timeout](robot_x == x2 && robot_y == y2))`` is
  checked on the generated pose trace by a real :class:`~continuum.engine.verification.stl_monitor.Monitor`.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.core.errors import InputError
from continuum.engine.verification.monitor_milp import MonitorAllocator
from continuum.engine.verification.stl_monitor import Monitor

__all__ = [
    "FORMAT",
    "KAIROS_TOPICS",
    "NAVIGATION_ASSERTION",
    "SCENARIOS",
    "Migration",
    "Navigation",
    "Period",
    "Scenario",
    "SimMonitor",
    "SimNode",
    "SimTopic",
    "SimulationResult",
    "kairos_scenario",
    "scenario",
    "simulate",
    "stats_document",
    "synthetic_scenario",
]

FORMAT = "continuum.abvsimulation/v1"
NAVIGATION_ASSERTION = "G((robot_x == x1 && robot_y == y1 && newGoal) -> F[0,timeout](robot_x == x2 && robot_y == y2))"


# ===================================================================================================
# Scenario description
# ===================================================================================================


@dataclass
class SimNode:
    name: str
    threshold: float = 100.0  # % CPU the node may reach with the verification (Eq. 3.22 capacity)
    background: list[tuple[float, float]] = field(default_factory=lambda: [(0.0, 0.0)])  # (from t, % CPU)
    spikes: list[tuple[float, float, float]] = field(default_factory=list)  # (from t, to t, extra %)
    speed: float = 1.0

    def load(self, t: float) -> float:
        """Background CPU at time t: the last step at or before t, plus any spike covering t."""
        value = self.background[0][1]
        for start, pct in self.background:
            if start <= t:
                value = pct
        value += sum(extra for lo, hi, extra in self.spikes if lo <= t < hi)
        return max(0.0, min(100.0, value))


@dataclass
class SimTopic:
    name: str
    publisher: str
    rate_hz: float = 10.0


@dataclass
class SimMonitor:
    name: str
    topics: list[str]
    cpu: dict[str, float]  # % CPU of one node, per node (the true cost the handlers measure)
    node: str  # where it runs at the start
    tolerant: bool = False


@dataclass
class Navigation:
    """The RB-Kairos mission legs and the makespan model (§4.5.2)."""

    jetson: str = "jetson"
    base_ms: float = 115.0
    per_monitor_ms: float = 25.0 / 201.0
    remote_ms: float = 10.0 - 51 * 25.0 / 201.0
    requirement_ms: float = 125.0
    legs_from: float = 5.0  # first newGoal (s)
    leg_every: float = 20.0  # a new leg every ... s
    leg_length: float = 8.0  # seconds of driving at the required rate
    timeout_ms: float = 12_000.0
    pose_hz: float = 5.0
    start: tuple[float, float] = (1.0, 2.0)
    goal: tuple[float, float] = (9.0, 2.0)

    def makespan(self, on_jetson: int, remote: bool) -> float:
        return self.base_ms + self.per_monitor_ms * on_jetson + (self.remote_ms if remote else 0.0)


@dataclass
class Scenario:
    name: str
    nodes: list[SimNode]
    topics: list[SimTopic]
    monitors: list[SimMonitor]
    delay_ms: dict[tuple[str, str], float]  # (publisher, receiver) -> ms; same node: local_delay_ms
    duration_s: float = 120.0
    period_s: float = 1.0
    verification_from: float = 0.0  # the monitors start running
    allocation_from: float = 0.0  # the coordinator's first allocation
    local_delay_ms: float = 0.1
    topic_cpu: float = 0.2  # % CPU of receiving one topic on a unit that does not publish it
    window: int = 10  # SMA filter of the statistics (spec 03 §10.2)
    migration_cpu: float = 0.05  # % CPU on both ends per monitor moved, during its period
    handover_ms: float = 20.0  # first sort + payload transfer of Fig. 3.43, on top of the T0 round trip
    navigation: Navigation | None = None
    noise: float = 0.0  # uniform ± % on the background, seeded
    seed: int = 0
    time_limit: float = 0.9  # MILP wall-clock budget per period, used only when work_limit is None
    #: MILP budget per solve in branch-and-bound nodes: the run is reproducible from its seed (a wall-clock
    #: budget stopped the solver at a different point on a loaded machine).
    work_limit: int | None = 2000

    def node(self, name: str) -> SimNode:
        return next(n for n in self.nodes if n.name == name)

    def delay(self, topic: SimTopic, receiver: str) -> float:
        if topic.publisher == receiver:
            return self.local_delay_ms
        return self.delay_ms.get((topic.publisher, receiver), self.delay_ms.get((receiver, topic.publisher), 0.0))

    def validate(self) -> None:
        names = [n.name for n in self.nodes]
        if len(set(names)) != len(names) or not names:
            raise InputError("scenario nodes must be a non-empty list of distinct names", "nodes")
        known = set(names)
        topics = {t.name: t for t in self.topics}
        for t in self.topics:
            if t.publisher not in known:
                raise InputError(f"topic {t.name!r}: unknown publisher {t.publisher!r}", "topics")
        for m in self.monitors:
            if m.node not in known:
                raise InputError(f"monitor {m.name!r}: unknown node {m.node!r}", "monitors")
            for topic in m.topics:
                if topic not in topics:
                    raise InputError(f"monitor {m.name!r}: unknown topic {topic!r}", "monitors")
            missing = [n for n in names if n not in m.cpu]
            if missing:
                raise InputError(f"monitor {m.name!r}: no CPU figure for node {missing[0]!r}", "monitors")
        if self.period_s <= 0 or self.duration_s <= 0:
            raise InputError("period and duration must be positive", "period_s")


# ===================================================================================================
# Results
# ===================================================================================================


@dataclass
class Migration:
    t: float
    monitor: str
    source: str
    target: str
    events_moved: int

    def to_dict(self) -> dict:
        return {"t": self.t, "monitor": self.monitor, "from": self.source, "to": self.target,
                "events_moved": self.events_moved}  # fmt: skip


@dataclass
class Period:
    t: float
    background: dict[str, float]  # % CPU of the system under verification (or testbench)
    verification: dict[str, float]  # % CPU the monitors actually get on each node
    demand: dict[str, float]  # % CPU the monitors would need on each node
    cpu: dict[str, float]  # total, capped at 100
    monitors: dict[str, int]
    dropped: dict[str, float]  # share of the tolerant monitors' events dropped on each node
    allocation: dict[str, Any] | None = None  # the MILP result computed at the end of this period
    makespan_ms: float | None = None

    def to_dict(self) -> dict:
        return {
            "t": self.t,
            "background": self.background,
            "verification": self.verification,
            "demand": self.demand,
            "cpu": self.cpu,
            "monitors": self.monitors,
            "dropped": self.dropped,
            "allocation": self.allocation,
            "makespan_ms": self.makespan_ms,
        }


@dataclass
class SimulationResult:
    scenario: str
    nodes: list[str]
    thresholds: dict[str, float]
    periods: list[Period]
    migrations: list[Migration]
    violations: list[dict] = field(default_factory=list)  # of the navigation assertion
    legs: list[dict] = field(default_factory=list)
    requirement_ms: float | None = None
    navigation_node: str | None = None
    placement: dict[str, str] = field(default_factory=dict)  # monitor -> node at the end

    def summary(self) -> dict:
        solve = [p.allocation["solve_time_ms"] for p in self.periods if p.allocation and not p.allocation["reused"]]
        out: dict[str, Any] = {
            "periods": len(self.periods),
            "migrations": len(self.migrations),
            "events_moved": sum(m.events_moved for m in self.migrations),
            "milp_mean_ms": round(sum(solve) / len(solve), 3) if solve else None,
            "milp_max_ms": round(max(solve), 3) if solve else None,
            "milp_solves": len(solve),
            "final_monitors": self.periods[-1].monitors if self.periods else {},
            "overloaded_periods": sum(1 for p in self.periods if any(p.dropped.values())),
        }
        spans = [p.makespan_ms for p in self.periods if p.makespan_ms is not None]
        if spans and self.navigation_node:
            counts = [p.monitors.get(self.navigation_node, 0) for p in self.periods]
            out.update(
                navigation_node=self.navigation_node,
                navigation_node_max_monitors=max(counts),
                navigation_node_final_monitors=counts[-1],
                moved_off_navigation_node=max(counts) - counts[-1],
            )
        if spans:
            out.update(
                makespan_first_ms=round(spans[0], 3),
                makespan_max_ms=round(max(spans), 3),
                makespan_final_ms=round(spans[-1], 3),
                requirement_ms=self.requirement_ms,
                periods_over_requirement=sum(1 for s in spans if s > (self.requirement_ms or math.inf) + 1e-9),
                navigation_violations=len(self.violations),
                legs_reached=sum(1 for leg in self.legs if leg["reached"] is not None),
                legs=len(self.legs),
            )
        return out

    def to_dict(self) -> dict:
        return {
            "format": FORMAT,
            "scenario": self.scenario,
            "nodes": self.nodes,
            "thresholds": self.thresholds,
            "periods": [p.to_dict() for p in self.periods],
            "migrations": [m.to_dict() for m in self.migrations],
            "violations": self.violations,
            "legs": self.legs,
            "placement": self.placement,
            "summary": self.summary(),
        }


# ===================================================================================================
# The loop
# ===================================================================================================


def simulate(scenario: Scenario, progress: Callable[[float, str], None] | None = None) -> SimulationResult:
    """Run the scenario period by period (see the module docstring)."""
    scenario.validate()
    rng = random.Random(scenario.seed)
    names = [n.name for n in scenario.nodes]
    topics = {t.name: t for t in scenario.topics}
    monitors = {m.name: m for m in scenario.monitors}
    where = {m.name: m.node for m in scenario.monitors}
    budget: dict[str, Any] = (
        {"time_limit": scenario.time_limit}
        if scenario.work_limit is None
        else {"time_limit": math.inf, "work_limit": scenario.work_limit}
    )
    allocator = MonitorAllocator(window=scenario.window, **budget)
    periods: list[Period] = []
    migrations: list[Migration] = []
    moving: list[Migration] = []  # ordered at the end of the previous period: they cost CPU in this one
    steps = round(scenario.duration_s / scenario.period_s)
    for step in range(steps + 1):
        t = round(step * scenario.period_s, 9)
        background = {}
        for n in scenario.nodes:
            jitter = rng.uniform(-scenario.noise, scenario.noise) if scenario.noise else 0.0
            background[n.name] = max(0.0, min(100.0, n.load(t) + jitter))
        running = t >= scenario.verification_from
        demand, tolerant_demand = _demand(scenario, topics, monitors, where if running else {}, names)
        for m in moving:  # the migration spike (Fig. 4.24)
            demand[m.source] += scenario.migration_cpu
            demand[m.target] += scenario.migration_cpu
        verification, dropped = {}, {}
        for j in names:
            room = max(0.0, 100.0 - background[j])
            hard = demand[j] - tolerant_demand[j]
            if demand[j] <= room + 1e-9:
                verification[j], dropped[j] = demand[j], 0.0
            elif tolerant_demand[j] > 0 and hard < room:
                # strategy 2: tolerant monitors drop old events until the node keeps up
                kept = (room - hard) / tolerant_demand[j]
                verification[j], dropped[j] = hard + tolerant_demand[j] * kept, 1.0 - kept
            else:
                # strategy 1 only: the monitors fall behind, the node is saturated
                verification[j], dropped[j] = room, 0.0
        counts = {j: 0 for j in names}
        if running:
            for j in where.values():
                counts[j] += 1
        period = Period(
            t=t,
            background={j: round(background[j], 6) for j in names},
            verification={j: round(verification[j], 6) for j in names},
            demand={j: round(demand[j], 6) for j in names},
            cpu={j: round(min(100.0, background[j] + verification[j]), 6) for j in names},
            monitors=counts,
            dropped={j: round(dropped[j], 6) for j in names},
        )
        if scenario.navigation is not None:
            nav = scenario.navigation
            on_jetson = counts.get(nav.jetson, 0)
            remote = running and any(j != nav.jetson for j in where.values())
            period.makespan_ms = round(nav.makespan(on_jetson if running else 0, remote), 6)
        moving = []
        if running and t >= scenario.allocation_from:
            doc = stats_document(scenario, topics, monitors, where, background)
            result = allocator.step(doc)
            period.allocation = {
                k: result.to_dict()[k]
                for k in (
                    "feasible",
                    "status",
                    "objective",
                    "solve_time_ms",
                    "overloaded",
                    "drop_events",
                    "gap",
                    "reused",
                )
            }
            period.allocation["migrations"] = len(result.migrations)
            for name in result.migrations:
                source, target = where[name], result.allocation[name]
                moved = Migration(t, name, source, target, _events_moved(scenario, topics, monitors[name], target))
                migrations.append(moved)
                moving.append(moved)
                where[name] = target
        periods.append(period)
        if progress is not None and step % 10 == 0:
            progress(100.0 * step / max(1, steps), f"t = {t:g} s, {len(migrations)} migrations")
    out = SimulationResult(
        scenario=scenario.name,
        nodes=names,
        thresholds={n.name: n.threshold for n in scenario.nodes},
        periods=periods,
        migrations=migrations,
        placement=dict(where),
    )
    if scenario.navigation is not None:
        out.requirement_ms = scenario.navigation.requirement_ms
        out.navigation_node = scenario.navigation.jetson
        out.legs, out.violations = _navigate(scenario.navigation, periods, scenario.period_s)
    return out


def _demand(
    scenario: Scenario,
    topics: Mapping[str, SimTopic],
    monitors: Mapping[str, SimMonitor],
    where: Mapping[str, str],
    names: Sequence[str],
) -> tuple[dict[str, float], dict[str, float]]:
    demand = dict.fromkeys(names, 0.0)
    tolerant = dict.fromkeys(names, 0.0)
    received: set[tuple[str, str]] = set()
    for name, j in where.items():
        m = monitors[name]
        demand[j] += m.cpu[j]
        if m.tolerant:
            tolerant[j] += m.cpu[j]
        received.update((k, j) for k in m.topics if topics[k].publisher != j)
    for _, j in received:
        demand[j] += scenario.topic_cpu
    return demand, tolerant


def stats_document(
    scenario: Scenario,
    topics: Mapping[str, SimTopic],
    monitors: Mapping[str, SimMonitor],
    where: Mapping[str, str],
    background: Mapping[str, float],
) -> dict:
    """What the handlers report in one period (``continuum.monitorstats/v1``): each monitor's CPU only on
    the unit where it runs (the allocator remembers, or scales by speed, the others)."""
    return {
        "format": "continuum.monitorstats/v1",
        "nodes": [
            {
                "name": n.name,
                "available_cpu": round(100.0 - background[n.name], 6),
                "threshold": n.threshold,
                "speed": n.speed,
            }
            for n in scenario.nodes
        ],
        "topics": [
            {
                "name": t.name,
                "delay": {n.name: scenario.delay(t, n.name) for n in scenario.nodes},
                "cpu": {n.name: 0.0 if n.name == t.publisher else scenario.topic_cpu for n in scenario.nodes},
            }
            for t in scenario.topics
        ],
        "monitors": [
            {
                "name": m.name,
                "topics": m.topics,
                "cpu": {where[m.name]: m.cpu[where[m.name]]},
                "current": where[m.name],
                "tolerant": m.tolerant,
            }
            for m in scenario.monitors
        ],
    }


def _events_moved(scenario: Scenario, topics: Mapping[str, SimTopic], monitor: SimMonitor, target: str) -> int:
    rate = sum(topics[k].rate_hz for k in monitor.topics)
    link = max((scenario.delay(topics[k], target) for k in monitor.topics), default=scenario.local_delay_ms)
    return math.ceil(rate * (2 * link + scenario.handover_ms) / 1000.0)


def _navigate(nav: Navigation, periods: list[Period], period_s: float) -> tuple[list[dict], list[dict]]:
    """Drive the mission legs with the makespan of each period and check the navigation assertion."""
    dt = 1.0 / nav.pose_hz
    end = periods[-1].t + period_s
    span = {round(p.t, 9): p.makespan_ms for p in periods}

    def makespan_at(t: float) -> float:
        value = span.get(round(math.floor(t / period_s + 1e-9) * period_s, 9))
        return nav.base_ms if value is None else value

    events: list[tuple[str, Any, float]] = []
    legs = []
    (x1, y1), (x2, y2) = nav.start, nav.goal
    distance = math.hypot(x2 - x1, y2 - y1)
    step = distance / (nav.leg_length * nav.pose_hz)  # progress per pose update at the required rate
    start = nav.legs_from
    while start + nav.timeout_ms / 1000.0 <= end:
        ts = start * 1000.0
        events += [("robot_x", x1, ts), ("robot_y", y1, ts), ("newGoal", True, ts)]
        progress, reached, t = 0.0, None, start + dt
        while t < min(start + nav.leg_every, end) - 1e-9:
            ms = t * 1000.0
            if reached is None:
                ok = makespan_at(t) <= nav.requirement_ms + 1e-9
                progress = max(0.0, progress + (step if ok else -step))  # too slow: wrong direction (§4.5.2)
                if progress >= distance - 1e-9:
                    reached = round(t - start, 6)
                    events += [("robot_x", x2, ms), ("robot_y", y2, ms)]
                else:
                    f = progress / distance
                    events += [("robot_x", round(x1 + f * (x2 - x1), 6), ms),
                               ("robot_y", round(y1 + f * (y2 - y1), 6), ms)]  # fmt: skip
            if abs(t - start - dt) < 1e-9:
                events.append(("newGoal", False, ms))
            t = round(t + dt, 9)
        legs.append({"start": start, "reached": reached})
        start += nav.leg_every
    constants = {"x1": x1, "y1": y1, "x2": x2, "y2": y2, "timeout": nav.timeout_ms}
    monitor = Monitor(NAVIGATION_ASSERTION, constants=constants)
    found = monitor.feed(events)
    found += monitor.tick(end * 1000.0)
    found += monitor.flush()
    return legs, [v.to_dict() for v in found]


# ===================================================================================================
# The thesis's two case studies
# ===================================================================================================


def synthetic_scenario(**overrides: Any) -> Scenario:
    """§4.5.1 / Fig. 4.22 (spec 03 §13.1, S-ABV1): edge, desktop (10 ms) and server (100 ms), 50 monitors
    over 5 topics published on the edge; per-monitor CPU 0.76 / 0.5 / 0.36 %, 0.2 % per topic received
    remotely (spec §14). The testbench (our reading of the timeline): the edge fills from t = 20 s (room for
    about 30 monitors at 22 s, none at 23 s); the desktop saturates at 40 s; the server keeps 8 % free
    from 65 s to 87 s; every load ends at 105 s. Monitors are tolerant (the thesis dropped events in the
    overload). No SMA on the statistics (window 1): the thesis migrates within a second of the load."""
    nodes = [
        SimNode("edge", background=[(0, 0.0), (20, 40.0), (21, 62.0), (22, 76.0), (23, 99.5), (105, 0.0)]),
        SimNode("desktop", background=[(0, 0.0), (40, 99.0), (105, 0.0)]),
        SimNode("server", background=[(0, 0.0), (65, 92.0), (87, 0.0)]),
    ]
    topics = [SimTopic(f"/t{k}", "edge", rate_hz=20.0) for k in range(5)]
    monitors = [
        SimMonitor(f"m{i:02d}", [f"/t{i % 5}", f"/t{(i + 1) % 5}"],
                   {"edge": 0.76, "desktop": 0.5, "server": 0.36}, "edge", tolerant=True)
        for i in range(50)
    ]  # fmt: skip
    delay = {("edge", "desktop"): 10.0, ("edge", "server"): 100.0, ("desktop", "server"): 100.0}
    params: dict[str, Any] = dict(
        name="synthetic-4.5.1", nodes=nodes, topics=topics, monitors=monitors, delay_ms=delay,
        duration_s=120.0, window=1, local_delay_ms=0.0, topic_cpu=0.2,
    )  # fmt: skip
    params.update(overrides)
    return Scenario(**params)


#: RB-Kairos navigation and mission topics (§4.5.2): (name, publisher, Hz). Names are ours; the thesis
#: lists the components (ORB-SLAM, move_base local/global planner, mission, arm and gripper planning).
KAIROS_TOPICS = [
    ("/camera/color/image_raw", "jetson", 8.0), ("/orb_slam/pose", "jetson", 8.0), ("/orb_slam/map", "jetson", 1.0),
    ("/move_base/local_plan", "jetson", 8.0), ("/cmd_vel", "jetson", 8.0), ("/odom", "jetson", 20.0),
    ("/scan_front", "jetson", 15.0), ("/scan_rear", "jetson", 15.0), ("/tf", "jetson", 30.0),
    ("/robot_pose", "jetson", 10.0), ("/obstacles", "jetson", 5.0), ("/local_costmap", "jetson", 2.0),
    ("/mission/state", "mcb", 2.0), ("/mission/goal", "mcb", 1.0), ("/arm/joint_states", "mcb", 50.0),
    ("/gripper/state", "mcb", 10.0), ("/arm/planning", "mcb", 2.0), ("/battery", "mcb", 1.0),
    ("/move_base/global_plan", "server", 1.0), ("/hmi/commands", "server", 1.0),
]  # fmt: skip


def kairos_scenario(**overrides: Any) -> Scenario:
    """§4.5.2 / Fig. 4.24 (spec 03 §13.2, S-ABV2): MCB, Jetson Xavier NX and server with the thesis's
    thresholds (40 / 60 / 90 %), 201 monitors that all start on the Jetson, SMA(10) statistics.

    Our readings (documented, the thesis gives no per-monitor figures):
      * background CPU: Table 4.36's "no monitors" column (MCB 23.44 %, Jetson 38.64 %, server 30.96 %);
        the MCB's arm and gripper planning raises it to 39 % from t = 29 s to t = 85 s (Fig. 4.24: at 29 s
        the MCB reaches its threshold and monitors leave it for the server; at 85 s they come back); the
        server's Prometheus scrapes add 20 % for one second every 15 s (the thesis notes them).
      * per-monitor CPU: Jetson 0.415 % (its 60 % threshold then holds 51 monitors, the number the thesis
        kept there after 150 left), MCB 0.30 %, server 0.13 % (Table 4.36: +20 % on the server with about
        150 monitors); 0.05 % per topic received from another unit.
      * links: on-board Ethernet 0.5 ms, WiFi to the server 6 ms.
      * 201 monitors from 24 assertion families (one template over the same 1-3 topics, several parameter
        values; 18 families over navigation topics, 6 over mission topics; seeded); the coordinator
        allocates from t = 20 s (after the first mission leg ran with every monitor on the Jetson, as in
        the thesis).
    """
    rng = random.Random(overrides.pop("monitor_seed", 7))
    nodes = [
        SimNode("mcb", threshold=40.0, background=[(0, 23.44), (29, 39.0), (85, 23.44)], speed=1.4),
        SimNode("jetson", threshold=60.0, background=[(0, 38.64)], speed=1.0),
        SimNode("server", threshold=90.0, background=[(0, 30.96)], speed=3.2,
                spikes=[(s, s + 1, 20.0) for s in (12, 57, 102)]),
    ]  # fmt: skip
    topics = [SimTopic(n, p, hz) for n, p, hz in KAIROS_TOPICS]
    nav = [t.name for t in topics if t.publisher == "jetson"]
    mission = [t.name for t in topics if t.publisher != "jetson"]
    # assertions come in families over the same signals (one template, several parameters): 24 topic
    # patterns, 18 over the navigation topics and 6 over the mission's
    patterns = [rng.sample(nav, rng.randint(1, 3)) for _ in range(18)]
    patterns += [rng.sample(mission, rng.randint(1, 2)) for _ in range(6)]
    monitors = []
    for i in range(201):
        reads = patterns[i % len(patterns)]
        monitors.append(
            SimMonitor(f"m{i:03d}", reads, {"jetson": 0.415, "mcb": 0.30, "server": 0.13}, "jetson",
                       tolerant=i % 3 == 0)
        )  # fmt: skip
    delay = {("jetson", "mcb"): 0.5, ("jetson", "server"): 6.0, ("mcb", "server"): 6.0}
    params: dict[str, Any] = dict(
        name="rb-kairos-4.5.2", nodes=nodes, topics=topics, monitors=monitors, delay_ms=delay,
        duration_s=120.0, verification_from=5.0, allocation_from=20.0, window=10, topic_cpu=0.05,
        navigation=Navigation(),
    )  # fmt: skip
    params.update(overrides)
    return Scenario(**params)


SCENARIOS: dict[str, Callable[..., Scenario]] = {"kairos": kairos_scenario, "synthetic": synthetic_scenario}


def scenario(name: str, **overrides: Any) -> Scenario:
    if name not in SCENARIOS:
        raise InputError(f"unknown scenario {name!r} (choose from {', '.join(sorted(SCENARIOS))})", "scenario")
    return SCENARIOS[name](**overrides)
