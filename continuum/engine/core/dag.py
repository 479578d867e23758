"""Application DAGs: tasks with per-processor execution costs, edges with data sizes.

This is the ``continuum.dag/v1`` contract. A task's ``cost`` maps a processor id or a processor class to
its execution time there; the id wins over the class, and a processor that matches neither cannot run
the task (an exclusive implementation, thesis 3.1.1).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.core import limits
from continuum.engine.core.errors import InputError

__all__ = ["FORMAT", "Edge", "Task", "TaskGraph"]

FORMAT = "continuum.dag/v1"


@dataclass(frozen=True)
class Task:
    id: str
    cost: Mapping[str, float]
    critical: bool = False
    name: str = ""


@dataclass(frozen=True)
class Edge:
    src: str
    dst: str
    data: float = 0.0


@dataclass
class TaskGraph:
    """A validated application DAG. Build it with :meth:`from_dict` or the constructor + :meth:`validate`."""

    name: str
    tasks: dict[str, Task]
    edges: list[Edge]
    time_unit: str = "ms"
    meta: dict[str, Any] = field(default_factory=dict)

    # ---- construction -------------------------------------------------------------------------
    @classmethod
    def build(cls, name: str, tasks: Iterable[Task], edges: Iterable[Edge], **kwargs: Any) -> TaskGraph:
        """Build and validate; duplicate task ids are rejected."""
        table: dict[str, Task] = {}
        for task in tasks:
            if task.id in table:
                raise InputError(f"duplicate task id {task.id!r}", "tasks")
            table[task.id] = task
        graph = cls(name=name, tasks=table, edges=list(edges), **kwargs)
        graph.validate()
        return graph

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> TaskGraph:
        """Parse a ``continuum.dag/v1`` document, rejecting anything malformed with a precise message."""
        if not isinstance(data, Mapping):
            raise InputError("a DAG document must be a JSON object")
        fmt = data.get("format", FORMAT)
        if fmt != FORMAT:
            raise InputError(f"unsupported format {fmt!r}, expected {FORMAT!r}", "format")
        raw_tasks = data.get("tasks")
        if not isinstance(raw_tasks, list) or not raw_tasks:
            raise InputError("'tasks' must be a non-empty list", "tasks")
        limits.check("tasks", len(raw_tasks))
        tasks = [_parse_task(i, raw) for i, raw in enumerate(raw_tasks)]
        raw_edges = data.get("edges", [])
        if not isinstance(raw_edges, list):
            raise InputError("'edges' must be a list", "edges")
        limits.check("edges", len(raw_edges))
        edges = [_parse_edge(i, raw) for i, raw in enumerate(raw_edges)]
        return cls.build(
            str(data.get("name") or "dag"),
            tasks,
            edges,
            time_unit=str(data.get("time_unit", "ms")),
            meta=dict(data.get("meta") or {}),
        )

    def to_dict(self) -> dict[str, Any]:
        doc: dict[str, Any] = {"format": FORMAT, "name": self.name, "time_unit": self.time_unit}
        doc["tasks"] = []
        for t in self.tasks.values():
            item: dict[str, Any] = {"id": t.id, "cost": dict(t.cost)}
            if t.critical:
                item["critical"] = True
            if t.name:
                item["name"] = t.name
            doc["tasks"].append(item)
        doc["edges"] = [{"src": e.src, "dst": e.dst, "data": e.data} for e in self.edges]
        if self.meta:
            doc["meta"] = self.meta
        return doc

    # ---- structure ----------------------------------------------------------------------------
    def validate(self) -> None:
        # Every reader ends here (build() and from_dict()): the DAG-size limits hold for every format.
        limits.check("tasks", len(self.tasks))
        limits.check("edges", len(self.edges))
        entries, most = sum(len(t.cost) for t in self.tasks.values()), limits.get().cost_entries
        if entries > most:
            raise InputError(f"tasks: at most {most:,} cost entries in all (got {entries:,})", "tasks")
        most_value = limits.get().magnitude
        for t in self.tasks.values():
            for key, value in t.cost.items():
                if not (_finite_nonneg(value) and value <= most_value):
                    raise InputError(
                        f"task {t.id!r} has an invalid cost {value!r} on {key!r} (0 to {most_value:g})", "tasks"
                    )
        seen: set[tuple[str, str]] = set()
        for e in self.edges:
            for end in (e.src, e.dst):
                if end not in self.tasks:
                    raise InputError(f"edge {e.src}->{e.dst} refers to unknown task {end!r}", "edges")
            if e.src == e.dst:
                raise InputError(f"edge {e.src}->{e.dst} is a self-loop (cycle at task {e.src!r})", "edges")
            if (e.src, e.dst) in seen:
                raise InputError(f"duplicate edge {e.src}->{e.dst}", "edges")
            seen.add((e.src, e.dst))
            if not (_finite_nonneg(e.data) and e.data <= most_value):
                raise InputError(
                    f"edge {e.src}->{e.dst} has invalid data size {e.data!r} (0 to {most_value:g})", "edges"
                )
        self.topological_order()  # raises on a cycle

    def predecessors(self) -> dict[str, list[Edge]]:
        pred: dict[str, list[Edge]] = {t: [] for t in self.tasks}
        for e in self.edges:
            pred[e.dst].append(e)
        return pred

    def successors(self) -> dict[str, list[Edge]]:
        succ: dict[str, list[Edge]] = {t: [] for t in self.tasks}
        for e in self.edges:
            succ[e.src].append(e)
        return succ

    def topological_order(self) -> list[str]:
        """Kahn's algorithm in input order; raises :class:`InputError` naming a cycle."""
        indeg = dict.fromkeys(self.tasks, 0)
        succ = self.successors()
        for e in self.edges:
            indeg[e.dst] += 1
        ready = [t for t in self.tasks if indeg[t] == 0]
        order: list[str] = []
        i = 0
        while i < len(ready):
            t = ready[i]
            i += 1
            order.append(t)
            for e in succ[t]:
                indeg[e.dst] -= 1
                if indeg[e.dst] == 0:
                    ready.append(e.dst)
        if len(order) != len(self.tasks):
            raise InputError(f"the graph has a cycle: {' -> '.join(self._find_cycle(indeg))}", "edges")
        return order

    def _find_cycle(self, indeg: Mapping[str, int]) -> list[str]:
        # Every task left with a positive in-degree lies on or behind a cycle: walk predecessors among
        # them until a task repeats.
        left = {t for t, d in indeg.items() if d > 0}
        pred = self.predecessors()
        start = min(left)
        path, index = [start], {start: 0}
        while True:
            nxt = next(e.src for e in pred[path[-1]] if e.src in left)
            if nxt in index:
                cycle = [*path[index[nxt] :], nxt]
                return list(reversed(cycle))
            index[nxt] = len(path)
            path.append(nxt)

    def to_networkx(self):
        import networkx as nx

        g = nx.DiGraph(name=self.name)
        for t in self.tasks.values():
            g.add_node(t.id, cost=dict(t.cost), critical=t.critical)
        for e in self.edges:
            g.add_edge(e.src, e.dst, data=e.data)
        return g

    def __len__(self) -> int:
        return len(self.tasks)


def _finite_nonneg(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and x >= 0


def _parse_task(index: int, raw: Any) -> Task:
    if not isinstance(raw, Mapping):
        raise InputError(f"tasks[{index}] must be an object", "tasks")
    tid = raw.get("id")
    if isinstance(tid, int) and not isinstance(tid, bool):
        tid = str(tid)
    if not isinstance(tid, str) or not tid:
        raise InputError(f"tasks[{index}] has no string 'id'", "tasks")
    cost = raw.get("cost")
    if not isinstance(cost, Mapping) or not cost:
        raise InputError(f"task {tid!r} has no 'cost' (a map of processor id or class to time)", "tasks")
    for key, value in cost.items():
        if not _finite_nonneg(value):
            raise InputError(f"task {tid!r} has an invalid cost {value!r} on {key!r}", "tasks")
    return Task(
        id=tid,
        cost={str(k): float(v) for k, v in cost.items()},
        critical=bool(raw.get("critical", False)),
        name=str(raw.get("name", "")),
    )


def _parse_edge(index: int, raw: Any) -> Edge:
    if not isinstance(raw, Mapping):
        raise InputError(f"edges[{index}] must be an object", "edges")
    src, dst = raw.get("src"), raw.get("dst")
    src = str(src) if isinstance(src, (int, str)) and not isinstance(src, bool) else None
    dst = str(dst) if isinstance(dst, (int, str)) and not isinstance(dst, bool) else None
    if not src or not dst:
        raise InputError(f"edges[{index}] needs 'src' and 'dst' task ids", "edges")
    data = raw.get("data", 0.0)
    if not _finite_nonneg(data):
        raise InputError(f"edge {src}->{dst} has invalid data size {data!r}", "edges")
    return Edge(src, dst, float(data))
