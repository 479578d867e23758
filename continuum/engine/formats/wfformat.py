"""WfCommons WfFormat 1.5 (https://github.com/wfcommons/WfFormat) workflow instances.

Task runtimes come from ``workflow.execution.tasks[].runtimeInSeconds`` and become a ``cpu`` class cost
in milliseconds. WfFormat has no edge weight: the data on an edge is the total size of the files the
parent writes and the child reads, converted to Mbit so that cluster links in Mbit/s apply directly.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..dag import Edge, Task, TaskGraph
from ..errors import InputError

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
        sizes[f["id"]] = float(f.get("sizeInBytes") or 0)
    runtimes = {}
    for i, t in enumerate((wf.get("execution") or {}).get("tasks") or []):
        if not isinstance(t, Mapping) or "id" not in t:
            raise InputError(f"WfFormat: workflow.execution.tasks[{i}] has no 'id'", "workflow")
        runtimes[t["id"]] = t.get("runtimeInSeconds")

    tasks, outputs, inputs, links = [], {}, {}, set()
    for i, t in enumerate(spec["tasks"]):
        if not isinstance(t, Mapping) or not t.get("id"):
            raise InputError(f"WfFormat: workflow.specification.tasks[{i}] has no 'id'", "workflow")
        tid = str(t["id"])
        runtime = runtimes.get(tid, t.get("runtimeInSeconds"))
        if runtime is None:
            raise InputError(f"WfFormat: task {tid!r} has no runtimeInSeconds in workflow.execution", "workflow")
        if not isinstance(runtime, (int, float)) or runtime < 0:
            raise InputError(f"WfFormat: task {tid!r} has invalid runtimeInSeconds {runtime!r}", "workflow")
        tasks.append(Task(tid, {"cpu": float(runtime) * 1000.0}, name=str(t.get("name", ""))))
        outputs[tid] = set(t.get("outputFiles") or [])
        inputs[tid] = set(t.get("inputFiles") or [])
        for parent in t.get("parents") or []:
            links.add((str(parent), tid))
        for child in t.get("children") or []:
            links.add((tid, str(child)))
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
