"""HEFT4K event-driven remapping after node failures (thesis 3.3.2, Algorithm 2, Fig. 3.31).

When computing nodes go offline, the tasks they ran (OT) must run elsewhere. Algorithm 2 decides between

- a *total* remap (the whole DAG is mapped again by HEFT on the surviving nodes, a temporary service
  interruption) when a task of OT is critical (``Task.critical``: losing it brings the application down) or
  when the HEFT ranks lost exceed a share ``threshold`` of the DAG's total rank (strictly greater, default
  20%: the thesis' calibration, Fig. 3.31);
- a *partial* remap otherwise: every unaffected task is locked to its current node and only OT is mapped,
  around the locked tasks, by the same HEFT pass with the *original* ranks (line 8 sorts before any change).

Readings (spec 02 section 8.2): the listing's 9999999 costs are implemented as "the candidate nodes of an
unaffected task are its current node" (same effect, but no sentinel distorting mean costs and ranks); the
HEFT call and the cost restore happen once, not per task; niceness follows Eq. 3.16 for every task with
the ranks the plan used (unchanged for locked tasks in a partial remap). HEFT_R is the upward rank, taken
from the current schedule when it carries ranks for every task. In a partial remap the locked tasks keep
their node but the new plan may re-time them (the predicted makespan is that plan's).
"""

from __future__ import annotations

import random
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Schedule
from continuum.engine.device.heft import upward_ranks
from continuum.engine.heft4k.heft4k import heft4k, map_dag, with_niceness

__all__ = [
    "CALIBRATION_STATISTICS",
    "MODES",
    "CalibrationPoint",
    "Evaluate",
    "RemapResult",
    "calibrate_threshold",
    "calibration_points",
    "decide",
    "remap",
]

MODES = ("partial", "total")


@dataclass
class RemapResult:
    """What Algorithm 2 decided and the new HEFT4K schedule (on the surviving nodes)."""

    schedule: Schedule
    mode: str  # "partial" or "total"
    failed: list[str]
    lost: list[str]  # OT: tasks that were on the failed nodes
    moved: list[str]  # tasks whose node changed
    critical_lost: list[str]
    lost_share: float  # sum of lost ranks / sum of all ranks
    threshold: float
    makespan_before: float
    makespan_after: float
    elapsed_ms: float
    reason: str = ""
    extra: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {
            "mode": self.mode,
            "reason": self.reason,
            "failed": list(self.failed),
            "lost": list(self.lost),
            "moved": list(self.moved),
            "critical_lost": list(self.critical_lost),
            "lost_share": self.lost_share,
            "threshold": self.threshold,
            "makespan_before": self.makespan_before,
            "makespan_after": self.makespan_after,
            "elapsed_ms": self.elapsed_ms,
        }


def decide(
    dag: TaskGraph, ranks: dict[str, float], lost: Iterable[str], threshold: float = 0.2
) -> tuple[str, str, float, list[str]]:
    """Algorithm 2 lines 2-3: (mode, reason, lost rank share, critical tasks lost)."""
    lost = list(lost)
    total = sum(ranks.values())
    share = sum(ranks[t] for t in lost) / total if total > 0 else 0.0
    critical = sorted(t for t in lost if dag.tasks[t].critical)
    if critical:
        return "total", f"critical task {critical[0]!r} was lost", share, critical
    if share > threshold:
        return "total", f"lost rank share {share:.1%} > threshold {threshold:.0%}", share, critical
    return "partial", f"lost rank share {share:.1%} <= threshold {threshold:.0%}", share, critical


def remap(
    schedule: Schedule,
    dag: TaskGraph,
    platform: Platform,
    failed: Sequence[str],
    *,
    threshold: float = 0.2,
    mode: str | None = None,
    lookahead: bool = True,
    nice_high: int = 0,
    nice_low: int = 19,
    rounding: str = "half-up",
) -> RemapResult:
    """Algorithm 2: remap ``schedule`` (a HEFT4K schedule of ``dag`` on ``platform``) after ``failed`` nodes.

    ``mode`` forces "partial" or "total" (the threshold calibration compares both); by default the
    critical-task rule and ``threshold`` decide.
    """
    t0 = time.perf_counter()
    if not 0.0 <= threshold <= 1.0:
        raise InputError(f"threshold must be a fraction in [0, 1], not {threshold!r}", "threshold")
    if mode is not None and mode not in MODES:
        raise InputError(f"unknown remap mode {mode!r} (choose from {', '.join(MODES)})", "mode")
    failed = list(dict.fromkeys(failed))
    for node in failed:
        if node not in platform.index:
            raise InputError(f"unknown node {node!r} (the cluster has {', '.join(platform.index)})", "fail")
    node_of = _node_of(schedule, dag, platform)
    survivors = platform.without(failed)
    ranks = (
        dict(schedule.ranks)
        if all(t in schedule.ranks for t in dag.tasks)
        else upward_ranks(dag, platform, costs=platform.cost_table(dag))
    )
    lost = [t for t in dag.tasks if node_of[t] in failed]
    decided, reason, share, critical = decide(dag, ranks, lost, threshold)
    chosen = mode or decided
    if mode and mode != decided:
        reason = f"forced {mode} ({reason})"
    if chosen == "total":
        new = heft4k(dag, survivors, lookahead=lookahead, nice_high=nice_high, nice_low=nice_low, rounding=rounding)
    else:
        locked = {t: [node_of[t]] for t in dag.tasks if node_of[t] not in failed}
        plan = map_dag(dag, survivors, lookahead=lookahead, ranks=ranks, allowed=locked)
        new = with_niceness(plan, dag, nice_high=nice_high, nice_low=nice_low, rounding=rounding)
    new.params["remap"] = chosen
    after = {a.task: a.processor for a in new.assignments}
    moved = [t for t in dag.tasks if after[t] != node_of[t]]
    elapsed = (time.perf_counter() - t0) * 1000.0
    result = RemapResult(
        schedule=new,
        mode=chosen,
        failed=failed,
        lost=lost,
        moved=moved,
        critical_lost=critical,
        lost_share=share,
        threshold=threshold,
        makespan_before=schedule.makespan,
        makespan_after=new.makespan,
        elapsed_ms=elapsed,
        reason=reason,
    )
    new.metrics["remap"] = result.to_dict()
    return result


def _node_of(schedule: Schedule, dag: TaskGraph, platform: Platform) -> dict[str, str]:
    node_of: dict[str, str] = {}
    for a in schedule.assignments:
        if a.frame == 0:
            node_of[a.task] = a.processor
    for tid in dag.tasks:
        if tid not in node_of:
            raise InputError(f"task {tid!r} is not in the current schedule", "schedule")
        if node_of[tid] not in platform.index:
            raise InputError(f"task {tid!r} is on node {node_of[tid]!r}, which the cluster does not have", "schedule")
    return node_of


# ---- threshold calibration (Fig. 3.31) ---------------------------------------------------------------
@dataclass
class CalibrationPoint:
    """One single-node failure: the lost rank share and how much worse partial is than total remapping."""

    tasks: int
    node: str
    lost_share: float
    partial: float  # predicted makespan of the partial remap
    total: float  # predicted makespan of the total remap

    @property
    def gap(self) -> float:
        return self.partial / self.total - 1.0 if self.total > 0 else 0.0


Evaluate = Callable[[TaskGraph, Platform, Schedule], float]


def calibration_points(
    cases: Iterable[tuple[TaskGraph, Platform]],
    *,
    seed: int = 0,
    failures_per_dag: int = 1,
    evaluate: Evaluate | None = None,
) -> list[CalibrationPoint]:
    """Fig. 3.31 data: for each (DAG, cluster), map with HEFT4K, fail random nodes one at a time (seeded)
    and remap both ways. ``evaluate(dag, surviving platform, schedule)`` gives the makespan compared
    (default: the plan's predicted makespan; the benchmark passes the CFS simulator)."""
    rng = random.Random(seed)
    points = []
    for dag, platform in cases:
        plan = heft4k(dag, platform)
        nodes = [p.id for p in platform.processors]
        for node in rng.sample(nodes, min(failures_per_dag, len(nodes) - 1)):
            part = remap(plan, dag, platform, [node], mode="partial")
            full = remap(plan, dag, platform, [node], mode="total")
            if evaluate is None:
                m_part, m_full = part.makespan_after, full.makespan_after
            else:
                survivors = platform.without([node])
                m_part = evaluate(dag, survivors, part.schedule)
                m_full = evaluate(dag, survivors, full.schedule)
            points.append(CalibrationPoint(len(dag), node, part.lost_share, m_part, m_full))
    return points


CALIBRATION_STATISTICS = ("mean", "p90", "marginal")


def calibrate_threshold(
    points: Sequence[CalibrationPoint],
    delta: float = 0.10,
    thresholds: Sequence[float] | None = None,
    statistic: str = "mean",
) -> dict[str, Any]:
    """Spec 02 section 8.3: the threshold up to which partial remapping loses at most ``delta`` against a
    total remap. ``statistic`` says how the gaps are judged:

    - ``"mean"`` (the spec's reading): the largest threshold whose partial cases (lost share <= threshold)
      have a mean gap <= delta;
    - ``"p90"``: the same with the 90th percentile of the gaps (nine cases in ten within delta);
    - ``"marginal"``: raise the threshold step by step, judging only the cases the step adds (lost share in
      (previous, threshold]), and stop at the first step whose mean gap exceeds delta ("iterates over the
      threshold values until the delta is reached", thesis 3.3.2).

    Returns the threshold (``None`` if none qualifies) and the curve behind it.
    """
    if statistic not in CALIBRATION_STATISTICS:
        raise InputError(
            f"unknown statistic {statistic!r} (choose from {', '.join(CALIBRATION_STATISTICS)})", "statistic"
        )
    thresholds = sorted(thresholds or [round(0.05 * k, 2) for k in range(1, 11)])
    curve = []
    best = None
    stopped = False
    previous = -1.0
    for theta in thresholds:
        gaps = sorted(p.gap for p in points if p.lost_share <= theta)
        step = [p.gap for p in points if previous < p.lost_share <= theta]
        mean = sum(gaps) / len(gaps) if gaps else 0.0
        p90 = gaps[min(len(gaps) - 1, int(0.9 * len(gaps)))] if gaps else 0.0
        step_mean = sum(step) / len(step) if step else 0.0
        curve.append(
            {"threshold": theta, "cases": len(gaps), "mean_gap": mean, "p90_gap": p90, "step_cases": len(step),
             "step_mean_gap": step_mean}
        )  # fmt: skip
        previous = theta
        if statistic == "marginal":
            stopped = stopped or step_mean > delta
            if not stopped and gaps:
                best = theta
        elif gaps and (mean if statistic == "mean" else p90) <= delta:
            best = theta
    return {"delta": delta, "statistic": statistic, "threshold": best, "curve": curve}
