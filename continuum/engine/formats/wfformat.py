"""WfCommons WfFormat 1.5 (https://github.com/wfcommons/WfFormat) workflow instances.

Task runtimes come from ``workflow.execution.tasks[].runtimeInSeconds`` and become a ``cpu`` class cost
in milliseconds. WfFormat has no edge weight: the data on an edge is the total size of the files the
parent writes and the child reads, converted to Mbit so that cluster links in Mbit/s apply directly.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from continuum.engine.core import limits
from continuum.engine.core.dag import Edge, Task, TaskGraph
from continuum.engine.core.errors import InputError

__all__ = ["MBIT_PER_BYTE", "read"]

MBIT_PER_BYTE = 8 / 1e6


def read(doc: Any) -> TaskGraph:
    if not isinstance(doc, Mapping) or not isinstance(doc.get("workflow"), Mapping):
        raise InputError("not a WfFormat document: no 'workflow' object", "workflow")
    wf = doc["workflow"]
    spec = wf.get("specification")
    if not isinstance(spec, Mapping) or not isinstance(spec.get("tasks"), list):
        raise InputError("WfFormat: 'workflow.specification.tasks' must be a list", "workflow")
    sizes = {}
    for i, f in enumerate(spec.get("files") or []):
        if not isinstance(f, Mapping) or "id" not in f:
            raise InputError(f"WfFormat: workflow.specification.files[{i}] has no 'id'", "workflow")
        size = f.get("sizeInBytes") or 0
        if isinstance(size, bool) or not isinstance(size, (int, float)) or not 0 <= size < math.inf:
            where = f"workflow.specification.files[{i}]"
            raise InputError(f"WfFormat: {where} has invalid sizeInBytes {size!r}", "workflow")
        if not isinstance(f["id"], str):
            raise InputError(f"WfFormat: workflow.specification.files[{i}].id must be a string", "workflow")
        sizes[f["id"]] = float(size)
    runtimes = {}
    for i, t in enumerate((wf.get("execution") or {}).get("tasks") or []):
        if not isinstance(t, Mapping) or "id" not in t:
            raise InputError(f"WfFormat: workflow.execution.tasks[{i}] has no 'id'", "workflow")
        runtimes[t["id"]] = t.get("runtimeInSeconds")

    limits.check("tasks", len(spec["tasks"]))
    tasks, outputs, inputs, links = [], {}, {}, set()
    for i, t in enumerate(spec["tasks"]):
        if not isinstance(t, Mapping) or not t.get("id"):
            raise InputError(f"WfFormat: workflow.specification.tasks[{i}] has no 'id'", "workflow")
        tid = str(t["id"])
        runtime = runtimes.get(tid, t.get("runtimeInSeconds"))
        if runtime is None:
            raise InputError(f"WfFormat: task {tid!r} has no runtimeInSeconds in workflow.execution", "workflow")
        if isinstance(runtime, bool) or not isinstance(runtime, (int, float)) or not 0 <= runtime < math.inf:
            raise InputError(f"WfFormat: task {tid!r} has invalid runtimeInSeconds {runtime!r}", "workflow")
        tasks.append(Task(tid, {"cpu": float(runtime) * 1000.0}, name=str(t.get("name", ""))))
        outputs[tid] = set(_names(t, "outputFiles", tid))
        inputs[tid] = set(_names(t, "inputFiles", tid))
        for parent in _names(t, "parents", tid):
            links.add((parent, tid))
        for child in _names(t, "children", tid):
            links.add((tid, child))
    edges = []
    for src, dst in sorted(links):
        if src not in outputs or dst not in inputs:
            missing = src if src not in outputs else dst
            raise InputError(f"WfFormat: edge {src}->{dst} refers to unknown task {missing!r}", "workflow")
        shared = outputs[src] & inputs[dst]
        edges.append(Edge(src, dst, sum(sizes.get(f, 0.0) for f in shared) * MBIT_PER_BYTE))
    return TaskGraph.build(
        str(doc.get("name") or "workflow"),
        tasks,
        edges,
        time_unit="ms",
        meta={"source_format": "wfformat", "schema_version": str(doc.get("schemaVersion", "")), "data_unit": "Mbit"},
    )


def _names(task: Mapping, key: str, tid: str) -> list[str]:
    """A task's list of task or file names (``parents``, ``inputFiles``...): a list of strings or absent."""
    value = task.get(key)
    if value is None:
        return []
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        problem = f"{key} must be a list of names (strings), not {value!r:.80}"
        raise InputError(f"WfFormat: task {tid!r}: {problem}", "workflow")
    return value
