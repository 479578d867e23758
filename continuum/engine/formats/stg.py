"""Kasahara's Standard Task Graph Set (STG, https://www.kasahara.cs.waseda.ac.jp/schedule/).

Layout: the first line holds the number of tasks n, excluding the two dummy tasks; then one line per task
``id cost n_pred pred...`` for ids 0 .. n+1 (0 is the dummy entry and n+1 the dummy exit, both of cost 0);
lines starting with ``#`` are a statistics trailer. A first line that counts the dummies too (as several
published copies do) is accepted when exactly that many task lines follow, with a warning in
``meta["warnings"]``. Ids need not be in increasing order. STG graphs are
homogeneous and have no communication costs, so every task gets a ``cpu`` class cost equal to its STG
cost and every edge carries no data, unless options say otherwise:

- ``ccr``: give each edge the data ``ccr * mean task cost`` times a factor drawn uniformly from [0, 2]
  (seeded), so the communication-to-computation ratio is ``ccr`` on average (with unit bandwidth);
- ``processors`` and ``heterogeneity`` (beta): cost the task on processors ``p0 .. p{processors-1}``,
  each drawn uniformly from ``cost * [1 - beta/2, 1 + beta/2]`` (Topcuoglu et al.'s heterogeneity model,
  seeded); use a platform whose processor ids are ``p0 ..``;
- ``dummies=False`` drops the zero-cost entry and exit tasks.
"""

from __future__ import annotations

import math
import random

from continuum.engine.core.dag import Edge, Task, TaskGraph
from continuum.engine.core.errors import InputError

__all__ = ["MAX_PROCESSORS", "read"]

#: Most processors the ``processors`` option may cost tasks on (one cost per processor and task).
MAX_PROCESSORS = 1024


def read(
    text: str,
    *,
    ccr: float | None = None,
    processors: int | None = None,
    heterogeneity: float | None = None,
    seed: int = 0,
    dummies: bool = True,
) -> TaskGraph:
    rows: list[tuple[int, list[str]]] = []
    for lineno, line in enumerate(text.splitlines(), 1):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            break  # the statistics trailer
        rows.append((lineno, stripped.split()))
    if not rows:
        raise InputError("STG: the file is empty", "tasks")
    first_line, first = rows[0]
    if len(first) != 1 or not first[0].isdigit():
        raise InputError(f"STG line {first_line}: expected the number of tasks, got {' '.join(first)!r}", "tasks")
    n = int(first[0])
    total = n + 2
    mismatch = f"STG: line {first_line} announces {n} tasks (+2 dummies) but {len(rows) - 1} follow"
    dummies_counted = len(rows) - 1 == n and n >= 3
    if dummies_counted:
        # Several published copies count the two dummies in the first line. Exactly n task lines follow (not
        # n + 2); below, their ids must be 0 .. n-1 and tasks 0 and n-1 zero-cost dummies: then the reading
        # is unambiguous, and accepted with a warning.
        total = n
    elif len(rows) - 1 != total:
        raise InputError(mismatch, "tasks")
    costs: dict[int, int] = {}
    preds: dict[int, list[int]] = {}
    where: dict[int, int] = {}
    for lineno, fields in rows[1:]:
        try:
            values = [int(f) for f in fields]
        except ValueError:
            raise InputError(f"STG line {lineno}: non-integer field in {' '.join(fields)!r}", "tasks") from None
        if len(values) < 3:
            raise InputError(f"STG line {lineno}: expected 'id cost n_pred pred...'", "tasks")
        tid, cost, npred, *plist = values
        if not 0 <= tid < total:
            reading = f" ({n} task lines after a count of {n}: read as counting the dummies)" if dummies_counted else ""
            raise InputError(f"STG line {lineno}: task id {tid} outside 0..{total - 1}{reading}", "tasks")
        if tid in costs:
            raise InputError(f"STG line {lineno}: task {tid} already defined on line {where[tid]}", "tasks")
        if cost < 0:
            raise InputError(f"STG line {lineno}: task {tid} has negative cost {cost}", "tasks")
        if npred != len(plist):
            raise InputError(
                f"STG line {lineno}: task {tid} announces {npred} predecessors but lists {len(plist)}", "tasks"
            )
        for p in plist:
            if not 0 <= p < total:
                raise InputError(f"STG line {lineno}: task {tid} has unknown predecessor {p}", "edges")
        costs[tid], preds[tid], where[tid] = cost, plist, lineno
    warnings: list[str] = []
    if dummies_counted:
        if costs[0] != 0 or costs[total - 1] != 0:
            raise InputError(
                f"{mismatch}; nor does it count the dummies: tasks 0 and {total - 1} are not of cost 0", "tasks"
            )
        warnings.append(
            f"STG line {first_line}: {n} counts the two dummy tasks (the format excludes them); "
            f"read as {n - 2} tasks plus the dummies 0 and {n - 1}"
        )
    keep = set(costs) if dummies else set(costs) - {0, total - 1}
    rng = random.Random(seed)
    mean_cost = sum(costs[t] for t in keep) / len(keep) if keep else 0.0
    if processors is not None and (processors < 1 or int(processors) != processors or processors > MAX_PROCESSORS):
        raise InputError(f"STG: processors must be an integer in 1..{MAX_PROCESSORS}, not {processors!r}", "processors")
    if ccr is not None and (not math.isfinite(ccr) or ccr < 0 or not math.isfinite(2 * ccr * mean_cost)):
        raise InputError(f"STG: ccr must be a finite number >= 0 that keeps data sizes finite, not {ccr!r}", "ccr")
    beta = heterogeneity or 0.0
    if not 0 <= beta <= 2:
        raise InputError(f"STG: heterogeneity must lie in [0, 2], not {heterogeneity!r}", "heterogeneity")
    tasks = []
    for tid in sorted(keep):
        c = float(costs[tid])
        task_cost: dict[str, float]
        if processors:
            task_cost = {f"p{j}": c * rng.uniform(1 - beta / 2, 1 + beta / 2) for j in range(processors)}
        else:
            task_cost = {"cpu": c}
        tasks.append(Task(str(tid), task_cost))
    edges = []
    for tid in sorted(keep):
        for p in preds[tid]:
            if p in keep:
                data = ccr * mean_cost * rng.uniform(0, 2) if ccr else 0.0
                edges.append(Edge(str(p), str(tid), data))
    meta: dict = {"source_format": "stg"}
    if warnings:
        meta["warnings"] = warnings  # the callers show them: CLI on stderr, API as ``warnings``
    if ccr:
        meta["ccr"] = ccr
    if processors:
        meta["heterogeneity"] = beta
    return TaskGraph.build("stg", tasks, edges, meta=meta)
