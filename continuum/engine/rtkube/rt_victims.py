"""RT-Kube's cluster-level monitor: the reconcile phase and the recovery response time (thesis 3.4).

Plain data in, decisions out, so the Django app (on each stored Monitoring report) and a Kubernetes
operator can both call it; nothing here talks to a cluster.

Reconcile (Fig. 3.36, spec 03 section 5.4), for one Monitoring report of container ``c`` on node ``i``:

1. **Violation** -- ``missedDeadlinesPeriod > threshold_period`` or ``missedDeadlinesTotal >
   threshold_total`` (strictly greater: "higher than"). Either threshold can be switched off (``None``).
2. **Victim** -- among the containers on ``i``: not ``c``, criticality lower than ``c``'s
   (``NONE < A < B < C``), not ``C``, and stateless. Three policies (thesis 3.4):

   * ``linear`` (O(n)): one pass; the lowest class that has a candidate, and in it the highest use of
     one resource (``linear_resource``: cpu or memory).
   * ``linearithmic`` (O(n log n)): sort by class, then by ``cpu/cpu_node + mem/mem_node`` (highest
     first) [spec 03 PROPOSAL for "a combination of two resources"].
   * ``quadratic`` (O(n^2)): per candidate, the traffic it exchanges with the containers that stay on
     ``i`` (pairwise); lowest class, then lowest traffic, then highest combined use [spec 03 PROPOSAL;
     the thesis only says it "considers inter-container communication dependencies and task semantics"].

3. **Evict and taint** -- evict the victim and taint ``i`` for ``taint_duration`` so that the recreated
   pod lands elsewhere (a stateless migration). No candidate: no eviction, an alert.

[AMBIGUOUS] (spec 03 #6) After an eviction ``missedDeadlinesTotal`` stays above its threshold and would
trigger on every report. The total-based trigger is therefore skipped for the same container until
``cooldown`` has passed *and* its total has grown by more than ``threshold_total`` since the last action.

Response time (Eqs. 3.19-3.20): :func:`response_time` turns per-event timestamps (the miss that pushed
the container over its threshold, report sent and received, kill sent and received) into the
components of Table 4.35; :func:`response_time_bound` and :func:`rec_phase_bound` are the bounds.
Times are in whatever unit the caller uses (seconds here by default for taints).
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.core.errors import InputError
from continuum.engine.rtkube.rt_model import CRITICALITY_RANK, NONE, Taint, parse_criticality

__all__ = [
    "POLICIES",
    "VIOLATION_TAINT_KEY",
    "ClusterMonitor",
    "ContainerInfo",
    "MonitorPolicy",
    "MonitoringReport",
    "NodeCapacity",
    "ReconcileDecision",
    "ResponseTime",
    "candidates",
    "crossing_miss",
    "is_violation",
    "rec_phase_bound",
    "response_time",
    "response_time_bound",
    "select_linear",
    "select_linearithmic",
    "select_quadratic",
    "select_victim",
    "traffic_between",
]

POLICIES = ("linear", "linearithmic", "quadratic")
#: spec 03 section 5.4 [PROPOSAL]: the taint RT pods do not tolerate.
VIOLATION_TAINT_KEY = "rt.monitoring/violation"


@dataclass(frozen=True)
class MonitorPolicy:
    """The user-defined thresholds of the cluster-level monitor (model ``RTMonitorPolicy``, spec 03 5.3)."""

    threshold_period: int | None = 10
    threshold_total: int | None = None
    update_frequency_hz: float = 10.0
    eviction_policy: str = "linear"
    linear_resource: str = "cpu"
    taint_duration: float = 60.0
    #: ``None`` = the taint duration.
    cooldown: float | None = None
    taint_key: str = VIOLATION_TAINT_KEY

    def __post_init__(self) -> None:
        if self.threshold_period is None and self.threshold_total is None:
            raise InputError("set at least one of threshold_period and threshold_total", "threshold_period")
        for name in ("threshold_period", "threshold_total"):
            v = getattr(self, name)
            if v is not None and (isinstance(v, bool) or not isinstance(v, int) or v < 0):
                raise InputError(f"{name} must be a non-negative integer, got {v!r}", name)
        if self.eviction_policy not in POLICIES:
            raise InputError(f"eviction_policy must be one of {', '.join(POLICIES)}", "eviction_policy")
        if self.linear_resource not in ("cpu", "memory"):
            raise InputError("linear_resource must be cpu or memory", "linear_resource")
        if not self.update_frequency_hz > 0:
            raise InputError("update_frequency_hz must be positive", "update_frequency_hz")
        if self.taint_duration < 0 or (self.cooldown is not None and self.cooldown < 0):
            raise InputError("taint_duration and cooldown must not be negative", "taint_duration")

    @property
    def cooldown_time(self) -> float:
        return self.taint_duration if self.cooldown is None else self.cooldown

    def to_dict(self) -> dict[str, Any]:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


@dataclass(frozen=True)
class MonitoringReport:
    """One container-level monitor update (Listing 3.37) plus the time it was received."""

    node: str
    container: str
    missed_period: int
    missed_total: int
    reported_at: float = 0.0

    @classmethod
    def from_dict(cls, doc: Mapping[str, Any], reported_at: float | None = None) -> MonitoringReport:
        """A ``Monitoring`` object (``apiVersion rt.monitoring/v1alpha1``) or its bare ``spec``."""
        spec = doc.get("spec", doc) if isinstance(doc, Mapping) else None
        if not isinstance(spec, Mapping):
            raise InputError("Monitoring: spec must be an object", "spec")
        for key in ("node", "containerName"):
            if not isinstance(spec.get(key), str) or not spec[key]:
                raise InputError(f"Monitoring: spec.{key} is required", key)
        counts = []
        for key in ("missedDeadlinesPeriod", "missedDeadlinesTotal"):
            v = spec.get(key)
            if isinstance(v, bool) or not isinstance(v, int) or v < 0:
                raise InputError(f"Monitoring {spec['containerName']!r}: spec.{key} must be an integer >= 0", key)
            counts.append(v)
        if counts[1] < counts[0]:
            raise InputError(
                f"Monitoring {spec['containerName']!r}: missedDeadlinesTotal {counts[1]} < missedDeadlinesPeriod "
                f"{counts[0]}",
                "missedDeadlinesTotal",
            )
        at = reported_at if reported_at is not None else spec.get("reportedAt", 0.0)
        return cls(spec["node"], spec["containerName"], counts[0], counts[1], float(at or 0.0))

    def to_dict(self, name: str | None = None) -> dict[str, Any]:
        return {
            "apiVersion": "rt.monitoring/v1alpha1",
            "kind": "Monitoring",
            "metadata": {"name": name or self.container},
            "spec": {
                "node": self.node,
                "containerName": self.container,
                "missedDeadlinesPeriod": self.missed_period,
                "missedDeadlinesTotal": self.missed_total,
            },
        }


@dataclass(frozen=True)
class ContainerInfo:
    """What the reconcile phase knows of a container on the node (its spec and, if known, its use)."""

    name: str
    criticality: str = NONE
    stateless: bool = False
    #: CPU use in cores (measured, or the request/utilization when nothing is measured).
    cpu: float = 0.0
    memory_mib: float = 0.0

    @property
    def rank(self) -> int:
        return CRITICALITY_RANK[self.criticality]

    @classmethod
    def from_dict(cls, doc: Mapping[str, Any]) -> ContainerInfo:
        name = doc.get("name")
        if not isinstance(name, str) or not name:
            raise InputError("container: name is required", "name")
        return cls(
            name,
            parse_criticality(doc.get("criticality"), f"container {name!r}"),
            bool(doc.get("stateless", False)),
            float(doc.get("cpu", 0.0)),
            float(doc.get("memory_mib", 0.0)),
        )


@dataclass(frozen=True)
class NodeCapacity:
    cpu: float = 1.0
    memory_mib: float = 1.0


def is_violation(report: MonitoringReport, policy: MonitorPolicy) -> str | None:
    """``"period"`` or ``"total"`` when that counter is strictly above its threshold, else ``None``."""
    if policy.threshold_period is not None and report.missed_period > policy.threshold_period:
        return "period"
    if policy.threshold_total is not None and report.missed_total > policy.threshold_total:
        return "total"
    return None


def candidates(violator: ContainerInfo, on_node: Iterable[ContainerInfo]) -> list[ContainerInfo]:
    """Containers that may be evicted for ``violator``: lower class, not C, stateless, not itself."""
    return [
        k
        for k in on_node
        if k.name != violator.name and k.rank < violator.rank and k.criticality != "C" and k.stateless
    ]


def _use(k: ContainerInfo, resource: str) -> float:
    return k.cpu if resource == "cpu" else k.memory_mib


def select_linear(cands: Sequence[ContainerInfo], resource: str = "cpu") -> ContainerInfo | None:
    """One pass: lowest class first, then the highest use of one resource, then the name."""
    best = None
    for k in cands:
        if best is None or (k.rank, -_use(k, resource), k.name) < (best.rank, -_use(best, resource), best.name):
            best = k
    return best


def _combined(k: ContainerInfo, cap: NodeCapacity) -> float:
    return (k.cpu / cap.cpu if cap.cpu else 0.0) + (k.memory_mib / cap.memory_mib if cap.memory_mib else 0.0)


def select_linearithmic(cands: Sequence[ContainerInfo], capacity: NodeCapacity) -> ContainerInfo | None:
    """Sort by class, then by ``cpu/cpu_node + mem/mem_node`` (highest first); take the first."""
    ranked = sorted(cands, key=lambda k: (k.rank, -_combined(k, capacity), k.name))
    return ranked[0] if ranked else None


def traffic_between(traffic: Mapping[Any, float], a: str, b: str) -> float:
    """Traffic between two containers; ``traffic`` maps ``(a, b)`` pairs or ``"a|b"`` keys, in any direction."""
    total = 0.0
    for key in ((a, b), (b, a), f"{a}|{b}", f"{b}|{a}"):
        total += float(traffic.get(key, 0.0))
    return total


def select_quadratic(
    cands: Sequence[ContainerInfo],
    on_node: Sequence[ContainerInfo],
    capacity: NodeCapacity,
    traffic: Mapping[Any, float] | None = None,
) -> ContainerInfo | None:
    """Lowest class, then the least traffic with the containers that stay on the node, then most use."""
    t = traffic or {}
    best_key, best = None, None
    for k in cands:
        penalty = sum(traffic_between(t, k.name, o.name) for o in on_node if o.name != k.name)
        key = (k.rank, penalty, -_combined(k, capacity), k.name)
        if best_key is None or key < best_key:
            best_key, best = key, k
    return best


def select_victim(
    violator: ContainerInfo,
    on_node: Sequence[ContainerInfo],
    policy: MonitorPolicy,
    capacity: NodeCapacity | None = None,
    traffic: Mapping[Any, float] | None = None,
) -> ContainerInfo | None:
    cands = candidates(violator, on_node)
    cap = capacity or NodeCapacity()
    if policy.eviction_policy == "linear":
        return select_linear(cands, policy.linear_resource)
    if policy.eviction_policy == "linearithmic":
        return select_linearithmic(cands, cap)
    return select_quadratic(cands, on_node, cap, traffic)


@dataclass(frozen=True)
class ReconcileDecision:
    """What the reconcile phase decided for one report."""

    container: str
    node: str
    trigger: str | None = None
    victim: str | None = None
    taint: Taint | None = None
    alert: str | None = None
    skipped: str | None = None
    candidates: tuple[str, ...] = ()

    @property
    def evict(self) -> bool:
        return self.victim is not None

    def to_dict(self) -> dict[str, Any]:
        return {
            "container": self.container,
            "node": self.node,
            "trigger": self.trigger,
            "victim": self.victim,
            "taint": self.taint.to_dict() if self.taint else None,
            "alert": self.alert,
            "skipped": self.skipped,
            "candidates": list(self.candidates),
        }


@dataclass
class ClusterMonitor:
    """The reconcile loop with its only state: when each container last caused an action (cooldown)."""

    policy: MonitorPolicy = field(default_factory=MonitorPolicy)
    #: container -> (time of the last action, its missedDeadlinesTotal then)
    last_action: dict[str, tuple[float, int]] = field(default_factory=dict)

    def reconcile(
        self,
        report: MonitoringReport,
        on_node: Sequence[ContainerInfo],
        capacity: NodeCapacity | None = None,
        traffic: Mapping[Any, float] | None = None,
        now: float | None = None,
    ) -> ReconcileDecision:
        t = report.reported_at if now is None else now
        trigger = is_violation(report, self.policy)
        if trigger is None:
            return ReconcileDecision(report.container, report.node)
        if trigger == "total" and report.container in self.last_action:
            since, total_then = self.last_action[report.container]
            grown = report.missed_total - total_then
            if t - since < self.policy.cooldown_time or grown <= (self.policy.threshold_total or 0):
                return ReconcileDecision(report.container, report.node, trigger, skipped="cooldown")
        violator = next((k for k in on_node if k.name == report.container), None)
        if violator is None:
            raise InputError(f"container {report.container!r} is not listed on node {report.node!r}", "containerName")
        cands = candidates(violator, on_node)
        victim = select_victim(violator, on_node, self.policy, capacity, traffic)
        self.last_action[report.container] = (t, report.missed_total)
        names = tuple(k.name for k in cands)
        if victim is None:
            alert = (
                f"{report.container} on {report.node} missed {report.missed_period} deadlines in the period "
                f"({report.missed_total} in total) and no container may be evicted"
            )
            return ReconcileDecision(report.container, report.node, trigger, alert=alert, candidates=names)
        taint = Taint(self.policy.taint_key, "true", "NoSchedule", until=t + self.policy.taint_duration)
        return ReconcileDecision(report.container, report.node, trigger, victim.name, taint, candidates=names)

    def forget(self, container: str) -> None:
        """A new instance of the container starts from zero counters."""
        self.last_action.pop(container, None)


# ---- response time (Eqs. 3.19-3.20) ----------------------------------------------------------------------------
@dataclass(frozen=True)
class ResponseTime:
    """The components of Table 4.35; ``total = update_wait + trans_json + reconcile + trans_kill``."""

    update_wait: float
    trans_json: float
    reconcile: float
    trans_kill: float

    @property
    def rec_phase(self) -> float:
        """Eq. 3.20's Rec_phase, which includes the kill message."""
        return self.reconcile + self.trans_kill

    @property
    def total(self) -> float:
        """RT_i^c of Eq. 3.19."""
        return self.update_wait + self.trans_json + self.rec_phase

    def to_dict(self) -> dict[str, float]:
        return {"update_wait": self.update_wait, "trans_json": self.trans_json, "reconcile": self.reconcile,
                "trans_kill": self.trans_kill, "rec_phase": self.rec_phase, "total": self.total}  # fmt: skip


def response_time(
    miss: float, report_sent: float, report_received: float, kill_sent: float, kill_received: float
) -> ResponseTime:
    """Eq. 3.19 from timestamps: the miss that crossed the threshold, the report, the kill message."""
    stamps = [miss, report_sent, report_received, kill_sent, kill_received]
    if any(b < a for a, b in itertools.pairwise(stamps)):
        raise InputError(f"response-time timestamps must not decrease: {stamps}", "timestamps")
    return ResponseTime(report_sent - miss, report_received - report_sent, kill_sent - report_received,
                        kill_received - kill_sent)  # fmt: skip


def crossing_miss(miss_times: Sequence[float], threshold: int, since: float = float("-inf")) -> float | None:
    """The miss that pushes a counter (reset at ``since``) strictly above ``threshold``, if any."""
    counted = sorted(t for t in miss_times if t >= since)
    return counted[threshold] if len(counted) > threshold else None


def rec_phase_bound(n: int, n_rt: int, t_spec: float, t_crd: float, eviction_phase: float, trans_kill: float) -> float:
    """Eq. 3.20: ``2 n t_SPEC + n_RT t_CRD + Eviction_phase + HTTP_trans(Kill)``."""
    if n_rt > n or n < 0 or n_rt < 0:
        raise InputError(f"need 0 <= n_RT <= n, got n={n}, n_RT={n_rt}", "n_rt")
    return 2 * n * t_spec + n_rt * t_crd + eviction_phase + trans_kill


def response_time_bound(update_frequency: float, trans_json: float, rec_phase: float) -> float:
    """Eq. 3.19: ``1/f_c + HTTP_trans(JSON_c) + Rec_phase``."""
    if update_frequency <= 0:
        raise InputError("update frequency must be positive", "update_frequency_hz")
    return 1 / update_frequency + trans_json + rec_phase
