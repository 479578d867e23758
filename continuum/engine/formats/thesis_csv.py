"""The thesis authors' DAG simulator CSV (``FrancescoL96/DAG-Scheduling-Simulator``, ``orb_graph.csv``).

One row per node: ``name, levels, cpu_t[levels], gpu_t[levels], copy_t[levels], (dependency,
level_offset)*``. A node with ``levels = L`` is L tasks, one per image-pyramid level, named ``name_k``
(just ``name`` when L = 1). Level k of a node depends on level ``k + level_offset`` of each listed
dependency, when that level exists (so ``scale0, -1`` chains the levels of ``scale0``). A time of ``-1``
means there is no implementation on that kind of processor (an exclusive node); ``copy_t`` is the
CPU <-> GPU copy a level needs before it can start. The simulator adds that copy to the node when any of
its inputs was computed on the other kind; here it is the ``data`` of each incoming edge, which a board
platform (:func:`continuum.engine.device.board.board`, bandwidth 1) turns into the same time when one input
crosses. Times are in the simulator's units (ms).
"""

from __future__ import annotations

import csv
import io
import math

from continuum.engine.core.dag import Edge, Task, TaskGraph
from continuum.engine.core.errors import InputError

__all__ = ["read"]


def _time(value: str, lineno: int, what: str) -> float | None:
    try:
        x = float(value)
    except ValueError:
        raise InputError(f"thesis CSV line {lineno}: {what} is not a number: {value!r}", "tasks") from None
    if x == -1:
        return None
    if not math.isfinite(x) or x < 0:
        raise InputError(f"thesis CSV line {lineno}: {what} must be >= 0 or -1 (none), not {value!r}", "tasks")
    return x


def read(text: str) -> TaskGraph:
    rows: list[tuple[int, list[str]]] = []
    for lineno, fields in enumerate(csv.reader(io.StringIO(text)), 1):
        fields = [f.strip() for f in fields]
        if not fields or all(not f for f in fields) or fields[0].startswith("#"):
            continue
        rows.append((lineno, fields))
    if not rows:
        raise InputError("thesis CSV: the file has no rows", "tasks")
    nodes: dict[str, dict] = {}
    for lineno, fields in rows:
        name = fields[0]
        if not name:
            raise InputError(f"thesis CSV line {lineno}: empty node name", "tasks")
        if name in nodes:
            raise InputError(f"thesis CSV line {lineno}: node {name!r} already defined on line {nodes[name]['line']}")
        if len(fields) < 2 or not fields[1].isdigit() or int(fields[1]) < 1:
            got = fields[1] if len(fields) > 1 else "nothing"
            raise InputError(f"thesis CSV line {lineno}: node {name!r} needs a positive level count, got {got!r}")
        levels = int(fields[1])
        need = 2 + 3 * levels
        if len(fields) < need or (len(fields) - need) % 2:
            raise InputError(
                f"thesis CSV line {lineno}: node {name!r} with {levels} levels needs {need} fields plus "
                f"(dependency, level offset) pairs, got {len(fields)} fields",
                "tasks",
            )
        cpu = [_time(v, lineno, f"{name} cpu time") for v in fields[2 : 2 + levels]]
        gpu = [_time(v, lineno, f"{name} gpu time") for v in fields[2 + levels : 2 + 2 * levels]]
        copy = [_time(v, lineno, f"{name} copy time") or 0.0 for v in fields[2 + 2 * levels : need]]
        for k in range(levels):
            if cpu[k] is None and gpu[k] is None:
                raise InputError(f"thesis CSV line {lineno}: node {name!r} level {k} has neither a CPU nor a GPU time")
        deps = []
        for j in range(need, len(fields), 2):
            dep, offset = fields[j], fields[j + 1]
            try:
                deps.append((dep, int(offset)))
            except ValueError:
                raise InputError(
                    f"thesis CSV line {lineno}: node {name!r} dependency {dep!r} has a non-integer level offset "
                    f"{offset!r}",
                    "edges",
                ) from None
        nodes[name] = {"line": lineno, "levels": levels, "cpu": cpu, "gpu": gpu, "copy": copy, "deps": deps}

    def task_id(name: str, k: int) -> str:
        return name if nodes[name]["levels"] == 1 else f"{name}_{k}"

    tasks, edges = [], []
    for name, node in nodes.items():
        for k in range(node["levels"]):
            cost = {}
            if node["cpu"][k] is not None:
                cost["cpu"] = node["cpu"][k]
            if node["gpu"][k] is not None:
                cost["gpu"] = node["gpu"][k]
            tasks.append(Task(task_id(name, k), cost, name=name))
    for name, node in nodes.items():
        for dep, offset in node["deps"]:
            if dep not in nodes:
                raise InputError(f"thesis CSV line {node['line']}: node {name!r} depends on unknown node {dep!r}")
            for k in range(node["levels"]):
                j = k + offset
                if 0 <= j < nodes[dep]["levels"]:
                    edges.append(Edge(task_id(dep, j), task_id(name, k), node["copy"][k]))
    return TaskGraph.build("thesis-sim", tasks, edges, time_unit="ms", meta={"source_format": "thesis_csv"})
