"""The schedule type: what every algorithm returns and every consumer reads.

This is the ``continuum.schedule/v1`` contract. The same object is stored by the scheduling app (one row
per assignment), drawn as a Gantt chart, served by the API and turned into pod bindings by the Kubernetes
gateway, so there is exactly one representation of a placement.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform

__all__ = ["EPS", "FORMAT", "Assignment", "Schedule"]

FORMAT = "continuum.schedule/v1"
#: Slack for float comparisons when checking a schedule.
EPS = 1e-6


@dataclass(frozen=True)
class Assignment:
    task: str
    processor: str
    start: float
    finish: float
    frame: int = 0
    #: Linux niceness the task's process runs with (HEFT4K, Eq. 3.16); ``None`` when not set.
    niceness: int | None = None
    #: CPU of a multi-core processor (``Processor.cores``) the task runs on; ``None`` when not set.
    core: int | None = None

    def to_dict(self) -> dict[str, Any]:
        doc = {
            "task": self.task,
            "frame": self.frame,
            "processor": self.processor,
            "start": self.start,
            "finish": self.finish,
        }
        if self.niceness is not None:
            doc["niceness"] = self.niceness
        if self.core is not None:
            doc["core"] = self.core
        return doc


@dataclass
class Schedule:
    algorithm: str
    assignments: list[Assignment]
    ranks: dict[str, float] = field(default_factory=dict)
    params: dict[str, Any] = field(default_factory=dict)
    #: Further figures an algorithm reports (overlap, latency per frame...), all JSON-serialisable.
    metrics: dict[str, Any] = field(default_factory=dict)

    @property
    def makespan(self) -> float:
        return max((a.finish for a in self.assignments), default=0.0)

    def to_dict(self) -> dict[str, Any]:
        doc: dict[str, Any] = {
            "format": FORMAT,
            "algorithm": self.algorithm,
            "makespan": self.makespan,
            "ranks": dict(self.ranks),
            "assignments": [a.to_dict() for a in self.assignments],
        }
        if self.params:
            doc["params"] = dict(self.params)
        if self.metrics:
            doc["metrics"] = dict(self.metrics)
        return doc

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Schedule:
        if data.get("format", FORMAT) != FORMAT:
            raise InputError(f"unsupported format {data.get('format')!r}, expected {FORMAT!r}", "format")
        try:
            assignments = [
                Assignment(
                    str(a["task"]),
                    str(a["processor"]),
                    float(a["start"]),
                    float(a["finish"]),
                    int(a.get("frame", 0)),
                    None if a.get("niceness") is None else int(a["niceness"]),
                    None if a.get("core") is None else int(a["core"]),
                )
                for a in data.get("assignments", [])
            ]
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"malformed assignment: {exc}", "assignments") from exc
        return cls(
            algorithm=str(data.get("algorithm", "")),
            assignments=assignments,
            ranks={str(k): float(v) for k, v in (data.get("ranks") or {}).items()},
            params=dict(data.get("params") or {}),
            metrics=dict(data.get("metrics") or {}),
        )

    # ---- views --------------------------------------------------------------------------------
    def by_processor(self) -> dict[str, list[Assignment]]:
        rows: dict[str, list[Assignment]] = {}
        for a in sorted(self.assignments, key=lambda a: (a.start, a.finish)):
            rows.setdefault(a.processor, []).append(a)
        return rows

    def lookup(self) -> dict[tuple[str, int], Assignment]:
        return {(a.task, a.frame): a for a in self.assignments}

    def critical_path(self, dag: TaskGraph, platform: Platform) -> list[tuple[str, int]]:
        """The chain of assignments that fixes the makespan, from an entry task to the last one.

        Walk back from the assignment that finishes last: at each step take the predecessor (by data or
        by processor order) whose arrival equals the start time; stop when the task starts at its
        earliest possible moment for another reason (time 0 or a release).
        """
        if not self.assignments:
            return []
        table = self.lookup()
        pred = dag.predecessors()
        prev_on_proc: dict[tuple[str, int], Assignment] = {}
        for row in self.by_processor().values():
            for before, after in itertools.pairwise(row):
                prev_on_proc[(after.task, after.frame)] = before
        cur = max(self.assignments, key=lambda a: a.finish)
        path = [(cur.task, cur.frame)]
        while True:
            nxt: Assignment | None = None
            for e in pred.get(cur.task, []):
                p = table.get((e.src, cur.frame))
                if p is None:
                    continue
                arrival = p.finish + (
                    platform.comm_time(p.processor, cur.processor, e.data)
                    if p.processor in platform.index and cur.processor in platform.index
                    else 0.0
                )
                if abs(arrival - cur.start) <= EPS * max(1.0, cur.start):
                    nxt = p
                    break
            if nxt is None:
                on_proc = prev_on_proc.get((cur.task, cur.frame))
                if on_proc is not None and abs(on_proc.finish - cur.start) <= EPS * max(1.0, cur.start):
                    nxt = on_proc
            if nxt is None:
                break
            cur = nxt
            path.append((cur.task, cur.frame))
        path.reverse()
        return path

    def violations(self, dag: TaskGraph, platform: Platform) -> list[str]:
        """Everything wrong with this schedule for ``dag`` on ``platform`` (empty when valid).

        Checks: every task of every frame placed once, on a processor that can run it, for exactly its
        execution time; precedence including transfer time; no overlap on a processor, or on one core of a
        multi-core processor (``core`` set), and never more tasks at once than a processor has cores.
        """
        problems: list[str] = []
        table = self.lookup()
        frames = sorted({a.frame for a in self.assignments}) or [0]
        if len(table) != len(self.assignments):
            problems.append("a task is assigned more than once in one frame")
        for frame in frames:
            for tid, task in dag.tasks.items():
                a = table.get((tid, frame))
                if a is None:
                    problems.append(f"task {tid!r} (frame {frame}) is not scheduled")
                    continue
                if a.processor not in platform.index:
                    problems.append(f"task {tid!r} is on unknown processor {a.processor!r}")
                    continue
                cost = platform.cost(task, platform.processors[platform.index[a.processor]])
                if cost is None:
                    problems.append(f"task {tid!r} runs on {a.processor!r}, which has no implementation of it")
                elif abs((a.finish - a.start) - cost) > EPS * max(1.0, cost):
                    problems.append(f"task {tid!r} lasts {a.finish - a.start}, its cost there is {cost}")
        for e in dag.edges:
            for frame in frames:
                s, d = table.get((e.src, frame)), table.get((e.dst, frame))
                if s is None or d is None or s.processor not in platform.index or d.processor not in platform.index:
                    continue
                ready = s.finish + platform.comm_time(s.processor, d.processor, e.data)
                if d.start + EPS * max(1.0, ready) < ready:
                    problems.append(
                        f"edge {e.src}->{e.dst} (frame {frame}): {e.dst!r} starts at {d.start} "
                        f"before its input arrives at {ready}"
                    )
        cores = {p.id: p.cores for p in platform.processors}
        for proc, row in self.by_processor().items():
            lanes: dict[int | None, list[Assignment]] = {}
            for a in row:
                lanes.setdefault(a.core if cores.get(proc, 1) > 1 else None, []).append(a)
            for lane in lanes.values():
                for before, after in itertools.pairwise(lane):
                    if after.start + EPS * max(1.0, before.finish) < before.finish:
                        problems.append(
                            f"{before.task!r} and {after.task!r} overlap on {proc!r}"
                            + ("" if after.core is None or cores.get(proc, 1) == 1 else f" core {after.core}")
                            + f" ([{before.start}, {before.finish}) and [{after.start}, {after.finish}))"
                        )
            if cores.get(proc, 1) > 1:
                problems += _capacity_problems(proc, row, cores[proc])
        return problems


def _capacity_problems(proc: str, row: list[Assignment], cores: int) -> list[str]:
    """More tasks running at once on ``proc`` than it has cores, or a core index it does not have."""
    problems = [
        f"task {a.task!r} is on core {a.core} of {proc!r}, which has {cores} cores"
        for a in row
        if a.core is not None and not 0 <= a.core < cores
    ]
    busy = [a for a in row if a.finish > a.start]
    # Finishes sort before starts at the same instant, with the same float slack as the other checks.
    events = sorted([(a.start, 1) for a in busy] + [(a.finish - EPS * max(1.0, a.finish), -1) for a in busy])
    running = 0
    for t, step in events:
        running += step
        if running > cores:
            problems.append(f"{running} tasks run at once on {proc!r} at {t}, which has {cores} cores")
            break
    return problems
