"""Discrete-event simulator of RT containers on a cluster: kernel, orchestrator and monitors (spec 03, 14).

It drives the real RT-Kube code, not copies: placements come from :mod:`.rt_kube` (``schedule`` or the
``kube_default`` baseline, or a fixed mapping), and the cluster-level monitor is
:class:`.rt_victims.ClusterMonitor`.

Model (times are integer microseconds inside; inputs and outputs in milliseconds):

* **Kernel admission** (Eq. 2.4) when a container starts on a node: the sum of the admitted ``runtime /
  period`` plus the new one must not exceed ``rt_threshold``; otherwise ``sched_setattr`` fails, the
  container crash-loops (retried with Kubernetes' back-off) and misses every deadline meanwhile.
  The runtime is the node's WCET, or the container's largest WCET where it has none (an RT-unaware
  scheduler put it there).
* **Periodic jobs**: task ``i`` releases a job every ``P`` from a random phase, absolute deadline
  ``release + D``. Its demand is ``U(exec_low, exec_high) * WCET(node)``; with probability ``p_ov`` it
  overruns, ``U(1, overrun_high) * WCET``. ``p_ov`` grows with every stress (non-RT) container on the
  node and on nodes without an RT kernel; stress also slows execution by ``stress_slowdown`` each.
  A ``demand_factor`` per container models a hog whose real demand exceeds its declared WCET.
* **SCHED_DEADLINE**: global EDF on ``M`` cores with one hard Constant Bandwidth Server per task
  (budget = runtime, period ``P``): a job that exhausts the budget is throttled until the next period
  (deadline postponed by ``P``) and raises SIGXCPU (``SCHED_FLAG_DL_OVERRUN``).
* **SCHED_FIFO** [spec 03 PROPOSAL, not in the thesis]: global fixed priority ``96 + rank`` (C highest),
  FIFO within a priority, no budget; SIGXCPU when a job has run for its WCET (``RLIMIT_RTTIME``-like).
* **Deadline misses**: a job that completes after its deadline, or is unfinished when its deadline is
  before the horizon. The container-level monitor counts one violation per late or overrunning job at
  the moment it is detected (SIGXCPU or late completion) and reports every ``1/f_c``.
* **Reconcile**: a report reaches the master after ``http_ms``; :class:`ClusterMonitor` decides; the kill
  leaves ``reconcile_ms`` later and reaches the node after ``kill_ms``. The victim is removed, the node
  tainted, the pod recreated and scheduled again; it starts ``cold_start_ms`` after binding. Pending
  containers are retried every ``scheduler_period_ms`` and whenever capacity is freed.
"""

from __future__ import annotations

import heapq
import math
import random
from collections import deque
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from continuum.engine.core.errors import InputError
from continuum.engine.core.placement import Decision, PlacementPlan
from continuum.engine.rtkube import rt_kube
from continuum.engine.rtkube.rt_model import CRITICALITY_RANK, RTContainer, RTNode, Taint
from continuum.engine.rtkube.rt_victims import (
    ClusterMonitor,
    ContainerInfo,
    MonitoringReport,
    MonitorPolicy,
    NodeCapacity,
    ResponseTime,
    response_time,
)

__all__ = [
    "US",
    "ContainerStats",
    "Eviction",
    "NodeCPU",
    "Placer",
    "SimParams",
    "SimResult",
    "Simulator",
    "fixed_placer",
    "kube_default_placer",
    "rt_kube_placer",
    "simulate",
]

US = 1000  # microseconds per millisecond


def _us(ms: float) -> int:
    return round(ms * US)


@dataclass(frozen=True)
class SimParams:
    horizon_ms: float = 10_000.0
    policy: str = "deadline"
    seed: int = 0
    exec_low: float = 0.3
    exec_high: float = 1.0
    p_overrun: float = 0.0
    p_overrun_stress: float = 0.0
    p_overrun_non_rt_kernel: float = 0.0
    overrun_high: float = 1.5
    stress_slowdown: float = 0.0
    #: container -> factor on its sampled demand (a hog whose real runtime exceeds its WCET).
    demand_factor: Mapping[str, float] = field(default_factory=dict)
    #: containers whose kernel admission test is bypassed (Fig. 4.21's hog).
    bypass_admission: frozenset[str] = frozenset()
    #: non-RT containers that interfere (None: every non-RT container).
    stressors: frozenset[str] | None = None
    admission: bool = True
    monitor: MonitorPolicy | None = None
    http_ms: float = 3.0
    reconcile_ms: float = 20.0
    kill_ms: float = 3.0
    cold_start_ms: float = 1000.0
    start_delay_ms: float = 0.0
    scheduler_period_ms: float = 1000.0
    restart_backoff_ms: float = 10_000.0
    restart_backoff_max_ms: float = 300_000.0
    random_phase: bool = True
    record_reports: bool = False

    def __post_init__(self) -> None:
        if self.policy not in ("deadline", "fifo"):
            raise InputError(f"policy must be deadline or fifo, got {self.policy!r}", "policy")
        if not 0 < self.exec_low <= self.exec_high <= 1:
            raise InputError("need 0 < exec_low <= exec_high <= 1", "exec_low")
        if self.overrun_high < 1:
            raise InputError("overrun_high must be at least 1", "overrun_high")
        if self.horizon_ms <= 0:
            raise InputError("horizon_ms must be positive", "horizon_ms")


# ---- one node's CPU ----------------------------------------------------------------------------------------------
@dataclass
class _Job:
    release: int
    deadline: int
    remaining: int
    executed: int = 0
    signalled: bool = False


@dataclass
class _Task:
    key: str  # container name + instance
    container: str
    period: int
    deadline: int
    budget: int
    prio: int
    rng: random.Random
    wcet: int
    demand_factor: float
    next_release: int
    jobs: deque[_Job] = field(default_factory=deque)
    server_deadline: int = 0
    budget_left: int = 0
    throttled_until: int | None = None
    busy: int = 0
    started: int = 0
    # statistics
    released: int = 0
    completed: int = 0
    missed: int = 0
    overruns: int = 0
    max_lateness: int = 0
    max_response: int = 0


class NodeCPU:
    """Global EDF (with CBS) or global fixed-priority FIFO on ``cores`` identical cores."""

    def __init__(self, node: RTNode, policy: str, on_violation: Callable[[str, int], None]):
        self.node = node
        self.cores = max(1, int(node.cpu))
        self.policy = policy
        self.on_violation = on_violation
        self.t = 0
        self.tasks: dict[str, _Task] = {}
        self.ready: set[str] = set()
        self.releases: list[tuple[int, str]] = []
        self.replenish: list[tuple[int, str]] = []
        self.p_ov = 0.0
        self.slowdown = 1.0
        self.exec_range = (0.3, 1.0)
        self.overrun_high = 1.5
        self.busy = 0
        self.finished: list[_Task] = []

    # -- tasks --
    def add(self, task: _Task) -> None:
        self.tasks[task.key] = task
        heapq.heappush(self.releases, (task.next_release, task.key))

    def remove(self, key: str) -> _Task | None:
        """Kill a task: in-flight jobs are dropped, not counted as misses (the container is gone)."""
        task = self.tasks.pop(key, None)
        if task is None:
            return None
        self.ready.discard(key)
        task.released -= len(task.jobs)  # dropped with the container: neither met nor missed
        task.jobs.clear()
        self.finished.append(task)
        return task

    def _demand(self, task: _Task) -> int:
        if task.rng.random() < self.p_ov:
            factor = task.rng.uniform(1.0, self.overrun_high)
        else:
            factor = task.rng.uniform(*self.exec_range)
        return max(1, round(task.wcet * factor * self.slowdown * task.demand_factor))

    def _release(self, task: _Task, now: int) -> None:
        job = _Job(now, now + task.deadline, self._demand(task))
        idle = not task.jobs
        task.jobs.append(job)
        task.released += 1
        # CBS wake-up rule: keep the server's (deadline, budget) only if that bandwidth is still valid.
        stale = (
            task.server_deadline <= now or task.budget_left * task.period > (task.server_deadline - now) * task.budget
        )
        if self.policy == "deadline" and idle and task.throttled_until is None and stale:
            task.server_deadline = now + task.deadline
            task.budget_left = task.budget
        if task.throttled_until is None:
            self.ready.add(task.key)

    def _key(self, key: str) -> tuple:
        task = self.tasks[key]
        if self.policy == "deadline":
            return (task.server_deadline, key)
        return (-task.prio, task.jobs[0].release, key)

    def _signal(self, task: _Task, job: _Job, now: int) -> None:
        if not job.signalled:
            job.signalled = True
            self.on_violation(task.key, now)

    def _complete(self, task: _Task, now: int) -> None:
        job = task.jobs.popleft()
        task.completed += 1
        task.max_response = max(task.max_response, now - job.release)
        if now > job.deadline:
            task.missed += 1
            task.max_lateness = max(task.max_lateness, now - job.deadline)
            self._signal(task, job, now)
        if not task.jobs:
            self.ready.discard(task.key)

    def _process(self) -> None:
        now = self.t
        while self.releases and self.releases[0][0] <= now:
            _, key = heapq.heappop(self.releases)
            task = self.tasks.get(key)
            if task is None:
                continue
            self._release(task, now)
            task.next_release += task.period
            heapq.heappush(self.releases, (task.next_release, key))
        while self.replenish and self.replenish[0][0] <= now:
            _, key = heapq.heappop(self.replenish)
            task = self.tasks.get(key)
            if task is None or task.throttled_until is None:
                continue
            task.throttled_until = None
            task.server_deadline += task.period
            task.budget_left += task.budget
            if task.server_deadline < now:
                task.server_deadline = now + task.deadline
                task.budget_left = task.budget
            if task.jobs:
                self.ready.add(key)

    def _running(self) -> list[str]:
        if len(self.ready) <= self.cores:
            return list(self.ready)
        return heapq.nsmallest(self.cores, self.ready, key=self._key)

    def advance(self, until: int) -> None:
        """Run the node up to time ``until`` (events at ``until`` itself are handled by the next call)."""
        while True:
            self._process()
            running = self._running()
            nxt = until
            if self.releases:
                nxt = min(nxt, self.releases[0][0])
            if self.replenish:
                nxt = min(nxt, self.replenish[0][0])
            for key in running:
                task = self.tasks[key]
                job = task.jobs[0]
                nxt = min(nxt, self.t + job.remaining)
                if self.policy == "deadline":
                    nxt = min(nxt, self.t + task.budget_left)
                elif not job.signalled and job.executed < task.wcet:
                    nxt = min(nxt, self.t + task.wcet - job.executed)
            dt = nxt - self.t
            if dt > 0:
                for key in running:
                    task = self.tasks[key]
                    job = task.jobs[0]
                    job.remaining -= dt
                    job.executed += dt
                    task.busy += dt
                    if self.policy == "deadline":
                        task.budget_left -= dt
                self.busy += dt * len(running)
            self.t = nxt
            for key in running:
                task = self.tasks[key]
                job = task.jobs[0]
                if job.remaining <= 0:
                    self._complete(task, self.t)
                elif self.policy == "deadline" and task.budget_left <= 0:
                    # Runtime overrun: SIGXCPU, throttled until the next period of the server.
                    task.overruns += 1
                    self._signal(task, job, self.t)
                    task.throttled_until = task.server_deadline - task.deadline + task.period
                    heapq.heappush(self.replenish, (task.throttled_until, key))
                    self.ready.discard(key)
                elif self.policy == "fifo" and not job.signalled and job.executed >= task.wcet:
                    task.overruns += 1
                    self._signal(task, job, self.t)
            if self.t >= until:
                return

    def finalize(self, horizon: int) -> None:
        """Jobs still unfinished with a deadline inside the horizon are misses; later ones are not counted."""
        for task in list(self.tasks.values()) + self.finished:
            for job in task.jobs:
                if job.deadline <= horizon:
                    task.missed += 1
                else:
                    task.released -= 1
            task.jobs.clear()


# ---- the cluster ----------------------------------------------------------------------------------------------------
@dataclass
class _Instance:
    container: RTContainer
    number: int
    node: str | None = None
    status: str = "pending"  # pending, starting, running, rejected, killed
    key: str = ""
    missed_period: int = 0
    missed_total: int = 0
    crossing_period: int | None = None
    crossing_total: int | None = None
    restarts: int = 0
    start_time: int = 0
    rejected_jobs: int = 0
    rejected_since: int | None = None


@dataclass
class Eviction:
    time_ms: float
    node: str
    violator: str
    victim: str
    trigger: str
    response_time: ResponseTime | None
    new_node: str | None = None
    taint_until_ms: float | None = None

    def to_dict(self) -> dict[str, Any]:
        return {
            "time_ms": self.time_ms,
            "node": self.node,
            "violator": self.violator,
            "victim": self.victim,
            "trigger": self.trigger,
            "response_time_ms": self.response_time.to_dict() if self.response_time else None,
            "new_node": self.new_node,
            "taint_until_ms": self.taint_until_ms,
        }


@dataclass
class ContainerStats:
    name: str
    criticality: str
    node: str | None
    status: str
    jobs: int = 0
    missed: int = 0
    overruns: int = 0
    rejected: bool = False
    rejected_jobs: int = 0
    evictions: int = 0
    max_lateness_ms: float = 0.0
    cpu_use: float = 0.0

    @property
    def miss_ratio(self) -> float:
        return self.missed / self.jobs if self.jobs else 0.0

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "criticality": self.criticality,
            "node": self.node,
            "status": self.status,
            "jobs": self.jobs,
            "missed": self.missed,
            "overruns": self.overruns,
            "rejected": self.rejected,
            "rejected_jobs": self.rejected_jobs,
            "evictions": self.evictions,
            "max_lateness_ms": self.max_lateness_ms,
            "cpu_use": self.cpu_use,
        }


@dataclass
class SimResult:
    params: dict[str, Any]
    containers: dict[str, ContainerStats]
    evictions: list[Eviction]
    plans: list[PlacementPlan]
    node_busy: dict[str, float]
    admitted_utilization: dict[str, float]
    alerts: list[dict[str, Any]] = field(default_factory=list)
    reports: list[dict[str, Any]] = field(default_factory=list)
    pending: list[str] = field(default_factory=list)

    def by_class(self) -> dict[str, dict[str, Any]]:
        """Table 4.31's columns per criticality: rejected, % missed by running, % with rejected at 100 %.

        ``running+rejected = (n_running * running% + n_rejected * 100) / n_class`` (spec 03, 12.2).
        Containers still pending (RT-Kube keeps them out of the kernel) are neither running nor rejected;
        ``missed_with_pending_pct`` also counts them at 100 %, for a comparison where every task matters.
        """
        out: dict[str, dict[str, Any]] = {}
        for cls in ("A", "B", "C"):
            members = [s for s in self.containers.values() if s.criticality == cls]
            if not members:
                continue
            pending = [s for s in members if s.status == "pending"]
            running = [s for s in members if not s.rejected and s.status != "pending"]
            jobs = sum(s.jobs for s in running)
            missed = sum(s.missed for s in running)
            running_pct = 100.0 * missed / jobs if jobs else 0.0
            n_rej = len(members) - len(running) - len(pending)
            placed = len(running) + n_rej
            out[cls] = {
                "containers": len(members),
                "rejected": n_rej,
                "pending": len(pending),
                "missed_running_pct": running_pct,
                "missed_total_pct": (len(running) * running_pct + n_rej * 100.0) / placed if placed else 0.0,
                "missed_with_pending_pct": (len(running) * running_pct + (n_rej + len(pending)) * 100.0) / len(members),
                "jobs": jobs,
                "missed": missed,
            }
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "params": self.params,
            "by_class": self.by_class(),
            "containers": [s.to_dict() for s in self.containers.values()],
            "evictions": [e.to_dict() for e in self.evictions],
            "alerts": self.alerts,
            "pending": self.pending,
            "node_busy": self.node_busy,
            "admitted_utilization": self.admitted_utilization,
            "placements": [p.to_dict() for p in self.plans],
        }


Placer = Callable[[list[RTContainer], list[RTNode], rt_kube.Ledger, float], PlacementPlan]


def rt_kube_placer(params: rt_kube.RTKubeParams | None = None) -> Placer:
    def place(pending, nodes, ledger, now_ms):
        return rt_kube.schedule(pending, nodes, params, ledger, now=now_ms)

    return place


def kube_default_placer(seed: int = 0, pin: str | None = None) -> Placer:
    rng = random.Random(seed)

    def place(pending, nodes, ledger, now_ms):
        return rt_kube.kube_default(pending, nodes, ledger, rng, pin=pin, now=now_ms)

    return place


def fixed_placer(mapping: Mapping[str, str], fallback: Placer | None = None) -> Placer:
    """A hand-made mapping (``K3S best``, or a filter bypass); it applies to a container's first placement only.

    Containers it does not name, and recreated (evicted) ones, go to ``fallback``.
    """
    done: set[str] = set()

    def place(pending, nodes, ledger, now_ms):
        decisions, rest = [], []
        for c in sorted(pending, key=lambda c: (c.arrival, c.name)):
            node = mapping.get(c.name)
            if node is None or c.name in done or ledger.where(c.name):
                rest.append(c)
                continue
            done.add(c.name)
            ledger.reserve(c, node)
            decisions.append(Decision(c.name, node, None))
        plan = PlacementPlan("fixed", decisions, metrics={"utilization": ledger.utilization()})
        if rest and fallback:
            extra = fallback(rest, nodes, ledger, now_ms)
            plan.decisions.extend(extra.decisions)
            plan.metrics["utilization"] = ledger.utilization()
        return plan

    return place


class Simulator:
    """One run; see the module docstring for the model."""

    def __init__(
        self,
        containers: Sequence[RTContainer],
        nodes: Sequence[RTNode],
        placer: Placer,
        params: SimParams | None = None,
    ):
        self.p = params or SimParams()
        names = [c.name for c in containers]
        if len(set(names)) != len(names):
            raise InputError("duplicate container names", "containers")
        self.nodes = {n.name: n for n in nodes}
        self.containers = {c.name: c for c in containers}
        self.placer = placer
        self.monitor = ClusterMonitor(self.p.monitor) if self.p.monitor else None
        self.cpu = {n.name: NodeCPU(n, self.p.policy, self._violation) for n in nodes}
        for cpu in self.cpu.values():
            cpu.exec_range = (self.p.exec_low, self.p.exec_high)
            cpu.overrun_high = self.p.overrun_high
        self.ledger = rt_kube.Ledger.for_nodes(nodes)
        self.instances: dict[str, _Instance] = {}
        self.by_key: dict[str, _Instance] = {}
        self.pending: list[str] = []
        self.taints: dict[str, list[Taint]] = {n: [] for n in self.nodes}
        self.admitted: dict[str, dict[str, float]] = {n: {} for n in self.nodes}
        self.events: list[tuple[int, int, str, Any]] = []
        self.seq = 0
        self.plans: list[PlacementPlan] = []
        self.evictions: list[Eviction] = []
        self.alerts: list[dict[str, Any]] = []
        self.reports: list[dict[str, Any]] = []
        self.evict_count: dict[str, int] = {}
        self.killing: set[str] = set()
        self.scheduled_pass: set[int] = set()
        self.now = 0

    # -- event queue --
    def _at(self, t: int, kind: str, payload: Any = None) -> None:
        self.seq += 1
        heapq.heappush(self.events, (t, self.seq, kind, payload))

    def _schedule_pass(self, t: int) -> None:
        if t not in self.scheduled_pass:
            self.scheduled_pass.add(t)
            self._at(t, "schedule")

    # -- the run --
    def run(self) -> SimResult:
        horizon = _us(self.p.horizon_ms)
        for node in self.nodes:
            self._refresh_interference(node)
        for c in self.containers.values():
            self._at(_us(c.arrival), "create", c.name)
        while self.events and self.events[0][0] < horizon:
            t, _, kind, payload = heapq.heappop(self.events)
            for cpu in self.cpu.values():
                cpu.advance(t)
            self.now = t
            getattr(self, f"_on_{kind}")(payload)
        for cpu in self.cpu.values():
            cpu.advance(horizon)
            cpu.finalize(horizon)
        self.now = horizon
        return self._result(horizon)

    # -- orchestration --
    def _view(self) -> list[RTNode]:
        now_ms = self.now / US
        out = []
        for name, node in self.nodes.items():
            live = [t for t in self.taints[name] if t.active(now_ms)]
            out.append(node if not live else _with_taints(node, live))
        return out

    def _on_create(self, name: str) -> None:
        inst = _Instance(self.containers[name], self.evict_count.get(name, 0))
        self.instances[name] = inst
        self.pending.append(name)
        self._schedule_pass(self.now)

    def _on_schedule(self, _: Any) -> None:
        self.scheduled_pass.discard(self.now)
        if not self.pending:
            return
        todo = [self.containers[n] for n in self.pending]
        plan = self.placer(todo, self._view(), self.ledger, self.now / US)
        plan.metrics["time_ms"] = self.now / US
        self.plans.append(plan)
        placed = plan.placed()
        for name in list(self.pending):
            node = placed.get(name)
            if node is None:
                continue
            self.pending.remove(name)
            inst = self.instances[name]
            inst.node, inst.status = node, "starting"
            delay = self.p.cold_start_ms if inst.number > 0 else self.p.start_delay_ms
            self._at(self.now + _us(delay), "start", (name, inst.number))
            for ev in self.evictions:
                if ev.victim == name and ev.new_node is None:
                    ev.new_node = node
        if self.pending:
            self._schedule_pass(self.now + _us(self.p.scheduler_period_ms))

    def _declared(self, c: RTContainer, node: str) -> tuple[int, float]:
        wcet = c.wcet.get(node, max(c.wcet.values()))
        return _us(wcet), wcet / c.timing()[0]

    def _on_start(self, payload: tuple[str, int]) -> None:
        name, number = payload
        inst = self.instances.get(name)
        if inst is None or inst.number != number or inst.status not in ("starting", "rejected"):
            return
        c, node = inst.container, inst.node
        assert node is not None
        if not c.is_rt:
            inst.status = "running"
            self._refresh_interference(node)
            return
        period_ms, deadline_ms = c.timing()
        wcet_us, util = self._declared(c, node)
        admitted = self.admitted[node]
        total = math.fsum(admitted.values()) + util
        bypass = name in self.p.bypass_admission or not self.p.admission
        if not bypass and total > self.nodes[node].rt_threshold * (1 + rt_kube.ADMISSION_EPS):
            # sched_setattr fails: the container crashes and Kubernetes restarts it with a back-off.
            if inst.status != "rejected":
                inst.rejected_since = self.now
            inst.status = "rejected"
            backoff = min(self.p.restart_backoff_ms * 2**inst.restarts, self.p.restart_backoff_max_ms)
            inst.restarts += 1
            self._at(self.now + _us(backoff), "start", (name, number))
            return
        if inst.rejected_since is not None:
            inst.rejected_jobs += (self.now - inst.rejected_since) // _us(period_ms)
            inst.rejected_since = None
        admitted[name] = util
        inst.status = "running"
        inst.start_time = self.now
        inst.key = f"{name}#{number}"
        seed = f"{self.p.seed}:{name}:{number}"
        rng = random.Random(seed)
        period = _us(period_ms)
        phase = rng.randrange(period) if self.p.random_phase else 0
        task = _Task(
            key=inst.key,
            container=name,
            period=period,
            deadline=_us(deadline_ms),
            budget=wcet_us,
            prio=96 + CRITICALITY_RANK[c.criticality],
            rng=rng,
            wcet=wcet_us,
            demand_factor=float(self.p.demand_factor.get(name, 1.0)),
            next_release=self.now + phase,
            started=self.now,
        )
        self.cpu[node].add(task)
        self.by_key[inst.key] = inst
        if self.monitor and self.p.monitor is not None:
            f_us = _us(1000.0 / self.p.monitor.update_frequency_hz)
            self._at(self.now + rng.randrange(1, f_us + 1), "report", inst.key)

    def _refresh_interference(self, node: str) -> None:
        stress = sum(
            1
            for i in self.instances.values()
            if i.node == node
            and i.status == "running"
            and not i.container.is_rt
            and (self.p.stressors is None or i.container.name in self.p.stressors)
        )
        cpu = self.cpu[node]
        cpu.p_ov = min(
            1.0,
            self.p.p_overrun
            + self.p.p_overrun_stress * stress
            + (0.0 if self.nodes[node].rt else self.p.p_overrun_non_rt_kernel),
        )
        cpu.slowdown = 1.0 + self.p.stress_slowdown * stress

    # -- monitoring --
    def _violation(self, key: str, t: int) -> None:
        inst = self.by_key.get(key)
        if inst is None:
            return
        inst.missed_period += 1
        inst.missed_total += 1
        pol = self.p.monitor
        if pol is None:
            return
        if pol.threshold_period is not None and inst.missed_period == pol.threshold_period + 1:
            inst.crossing_period = t
        if pol.threshold_total is not None and inst.missed_total == pol.threshold_total + 1:
            inst.crossing_total = t

    def _on_report(self, key: str) -> None:
        inst = self.by_key.get(key)
        if inst is None or inst.key != key or inst.status != "running":
            return
        report = MonitoringReport(inst.node or "", inst.container.name, inst.missed_period, inst.missed_total)
        crossing = inst.crossing_period if inst.crossing_period is not None else inst.crossing_total
        if self.p.record_reports:
            self.reports.append({"time_ms": self.now / US, **report.to_dict()["spec"]})
        inst.missed_period = 0
        inst.crossing_period = None
        self._at(self.now + _us(self.p.http_ms), "reconcile", (report, key, self.now, crossing))
        assert self.p.monitor is not None  # reports are only scheduled with a monitor
        f_us = _us(1000.0 / self.p.monitor.update_frequency_hz)
        self._at(self.now + f_us, "report", key)

    def _container_info(self, inst: _Instance) -> ContainerInfo:
        c = inst.container
        if c.is_rt and inst.node is not None and inst.key in self.cpu[inst.node].tasks:
            task = self.cpu[inst.node].tasks[inst.key]
            elapsed = max(1, self.now - task.started)
            use = task.busy / elapsed
        else:
            use = c.cpu
        return ContainerInfo(c.name, c.criticality, c.stateless, use, c.memory_mib)

    def _on_reconcile(self, payload: tuple[MonitoringReport, str, int, int | None]) -> None:
        report, key, sent, crossing = payload
        inst = self.by_key.get(key)
        if inst is None or inst.status != "running" or self.monitor is None or report.container in self.killing:
            return
        node = report.node
        on_node = [
            self._container_info(i)
            for i in self.instances.values()
            if i.node == node and i.status == "running" and i.container.name not in self.killing
        ]
        cap = NodeCapacity(
            self.nodes[node].cpu, self.nodes[node].memory_mib if self.nodes[node].memory_mib < math.inf else 0
        )
        # The monitor policy counts in seconds (taint duration, cooldown); the simulator in ms/us.
        now_s = self.now / 1e6
        rep = MonitoringReport(report.node, report.container, report.missed_period, report.missed_total, now_s)
        decision = self.monitor.reconcile(rep, on_node, cap, now=now_s)
        if decision.alert:
            self.alerts.append({"time_ms": self.now / US, "node": node, "message": decision.alert})
        if not decision.evict:
            return
        assert decision.victim is not None and decision.trigger is not None  # set whenever evict is
        kill_sent = self.now + _us(self.p.reconcile_ms)
        kill_at = kill_sent + _us(self.p.kill_ms)
        self.killing.add(decision.victim)
        rt = None
        if crossing is not None:
            rt = response_time(crossing / US, sent / US, self.now / US, kill_sent / US, kill_at / US)
        assert decision.taint is not None and decision.taint.until is not None
        until_ms = decision.taint.until * 1000.0
        ev = Eviction(kill_at / US, node, report.container, decision.victim, decision.trigger, rt, None, until_ms)
        self.evictions.append(ev)
        # The taint is set at reconcile time (Fig. 3.36: taint before the eviction is initiated).
        self.taints[node].append(replace(decision.taint, until=until_ms))
        self._at(_us(until_ms), "taint_expired", node)
        self._at(kill_at, "kill", decision.victim)

    def _on_kill(self, name: str) -> None:
        self.killing.discard(name)
        inst = self.instances.get(name)
        if inst is None or inst.node is None:
            return
        node = inst.node
        if inst.key:
            self.cpu[node].remove(inst.key)  # its statistics stay in the node's finished list
        self.admitted[node].pop(name, None)
        self.ledger.release(name)
        inst.status = "killed"
        if not inst.container.is_rt:
            self._refresh_interference(node)
        if self.monitor:
            self.monitor.forget(name)
        self.evict_count[name] = self.evict_count.get(name, 0) + 1
        # The ReplicaSet recreates the pod at once; it goes back to the scheduler queue.
        new = _Instance(inst.container, self.evict_count[name])
        new.rejected_jobs = inst.rejected_jobs
        self.instances[name] = new
        self.pending.append(name)
        self._schedule_pass(self.now)

    def _on_taint_expired(self, node: str) -> None:
        now_ms = self.now / US
        self.taints[node] = [t for t in self.taints[node] if t.active(now_ms)]
        if self.pending:
            self._schedule_pass(self.now)

    # -- results --
    def _result(self, horizon: int) -> SimResult:
        stats: dict[str, ContainerStats] = {}
        tasks_by_container: dict[str, list[_Task]] = {}
        for cpu in self.cpu.values():
            for task in list(cpu.tasks.values()) + cpu.finished:
                tasks_by_container.setdefault(task.container, []).append(task)
        for name, c in self.containers.items():
            inst = self.instances.get(name)
            s = ContainerStats(name, c.criticality, inst.node if inst else None, inst.status if inst else "none")
            for task in tasks_by_container.get(name, []):
                s.jobs += task.released
                s.missed += task.missed
                s.overruns += task.overruns
                s.max_lateness_ms = max(s.max_lateness_ms, task.max_lateness / US)
                s.cpu_use += task.busy / horizon
            if c.is_rt and inst is not None:
                rejected_jobs = inst.rejected_jobs
                if inst.status == "rejected" and inst.rejected_since is not None:
                    rejected_jobs += max(0, horizon - inst.rejected_since) // _us(c.timing()[0])
                s.rejected = inst.status == "rejected"
                s.rejected_jobs = rejected_jobs
                # A rejected container misses every deadline it would have had (spec 03, 14).
                s.jobs += rejected_jobs
                s.missed += rejected_jobs
            s.evictions = self.evict_count.get(name, 0)
            stats[name] = s
        busy = {n: cpu.busy / (horizon * cpu.cores) for n, cpu in self.cpu.items()}
        admitted = {n: math.fsum(a.values()) for n, a in self.admitted.items()}
        params = {k: v for k, v in self.p.__dict__.items() if k not in ("monitor",)}
        params = {k: (sorted(v) if isinstance(v, frozenset) else dict(v) if isinstance(v, Mapping) else v)
                  for k, v in params.items()}  # fmt: skip
        params["monitor"] = self.p.monitor.to_dict() if self.p.monitor else None
        return SimResult(params, stats, self.evictions, self.plans, busy, admitted, self.alerts, self.reports,
                         list(self.pending))  # fmt: skip


def _with_taints(node: RTNode, extra: Iterable[Taint]) -> RTNode:
    return replace(node, taints=(*node.taints, *extra))


def simulate(
    containers: Sequence[RTContainer],
    nodes: Sequence[RTNode],
    placer: Placer | str = "rt_kube",
    params: SimParams | None = None,
    **placer_args: Any,
) -> SimResult:
    """Run one simulation; ``placer`` is ``"rt_kube"``, ``"k8s_default"`` (``seed``, ``pin``) or a callable."""
    if placer == "rt_kube":
        placer = rt_kube_placer(placer_args.get("rt_params"))
    elif placer == "k8s_default":
        placer = kube_default_placer(placer_args.get("seed", 0), placer_args.get("pin"))
    elif isinstance(placer, str):
        raise InputError(f"unknown placer {placer!r} (rt_kube, k8s_default or a callable)", "placer")
    return Simulator(containers, nodes, placer, params).run()
