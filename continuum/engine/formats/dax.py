"""Pegasus DAX workflows (the XML "abstract DAG" of Pegasus 2.x-4.x, schema DAX 2.1-3.6).

``<adag>`` holds ``<job id=... name=... runtime=...>`` elements, each with ``<uses file|name=...
link="input|output" size=...>`` children, and ``<child ref=...><parent ref=.../></child>`` dependencies.
A job's runtime (seconds) comes from its ``runtime`` attribute (the Pegasus workflow generator's
synthetic DAXes) or a ``<profile namespace="pegasus" key="runtime">`` child, and becomes a ``cpu`` class
cost in milliseconds. As with WfFormat, an edge's data is the total size of the files the parent writes
(``link="output"``) and the child reads (``link="input"``), converted from bytes to Mbit so that cluster
links in Mbit/s apply directly. ``dax:``/namespaced tags are accepted.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

from continuum.engine.core.dag import Edge, Task, TaskGraph
from continuum.engine.core.errors import InputError

__all__ = ["MBIT_PER_BYTE", "read"]

MBIT_PER_BYTE = 8 / 1e6


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _number(value: str | None, what: str) -> float:
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(f"DAX: {what} is not a number: {value!r}", "workflow") from None
    if not math.isfinite(x) or x < 0:
        raise InputError(f"DAX: {what} must be a non-negative number, not {value!r}", "workflow")
    return x


def read(text: str) -> TaskGraph:
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        line, col = exc.position
        raise InputError(f"DAX: malformed XML at line {line} column {col + 1}", "workflow") from None
    if _local(root.tag) != "adag":
        raise InputError(f"DAX: the root element is <{_local(root.tag)}>, expected <adag>", "workflow")
    tasks: list[Task] = []
    inputs: dict[str, dict[str, float]] = {}
    outputs: dict[str, dict[str, float]] = {}
    for k, job in enumerate(el for el in root if _local(el.tag) == "job"):
        jid = job.get("id")
        if not jid:
            raise InputError(f"DAX: <job> number {k + 1} has no id", "workflow")
        if jid in inputs:
            raise InputError(f"DAX: duplicate job id {jid!r}", "workflow")
        runtime = job.get("runtime")
        for child in job:
            if _local(child.tag) == "profile" and child.get("key") == "runtime" and runtime is None:
                runtime = (child.text or "").strip()
        if runtime is None:
            raise InputError(f"DAX: job {jid!r} has no runtime (attribute or pegasus profile)", "workflow")
        seconds = _number(runtime, f"job {jid!r} runtime")
        inputs[jid], outputs[jid] = {}, {}
        for use in job:
            if _local(use.tag) != "uses":
                continue
            fname = use.get("file") or use.get("name")
            if not fname:
                raise InputError(f"DAX: job {jid!r} has a <uses> without file or name", "workflow")
            link = (use.get("link") or "").lower()
            if link not in ("input", "output", "inout", "checkpoint"):
                raise InputError(f"DAX: job {jid!r} uses {fname!r} with unknown link {use.get('link')!r}", "workflow")
            size = _number(use.get("size", "0"), f"job {jid!r} file {fname!r} size")
            if link in ("input", "inout"):
                inputs[jid][fname] = size
            if link in ("output", "inout", "checkpoint"):
                outputs[jid][fname] = size
        tasks.append(Task(jid, {"cpu": seconds * 1000.0}, name=job.get("name", "")))
    if not tasks:
        raise InputError("DAX: the workflow has no <job>", "workflow")
    links: dict[tuple[str, str], None] = {}
    for child in (el for el in root if _local(el.tag) == "child"):
        ref = child.get("ref")
        if ref not in inputs:
            raise InputError(f"DAX: <child ref={ref!r}> names no job", "workflow")
        for parent in child:
            if _local(parent.tag) != "parent":
                continue
            pref = parent.get("ref")
            if pref not in inputs:
                raise InputError(f"DAX: <parent ref={pref!r}> of child {ref!r} names no job", "workflow")
            links[(pref, ref)] = None
    edges = []
    for src, dst in links:
        shared = outputs[src].keys() & inputs[dst].keys()
        data = sum(max(outputs[src][f], inputs[dst][f]) for f in shared)
        edges.append(Edge(src, dst, data * MBIT_PER_BYTE))
    return TaskGraph.build(
        root.get("name") or "dax",
        tasks,
        edges,
        time_unit="ms",
        meta={"source_format": "dax", "schema_version": root.get("version", ""), "data_unit": "Mbit"},
    )
