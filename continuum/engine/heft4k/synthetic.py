"""Random DAGs and clusters like the HEFT4K synthetic benchmark (thesis 4.3.2, Table 4.28).

The thesis does not describe its generator, only the ranges of Table 4.28; this is spec 02 section 12.2's
proposal, seeded:

- size ``n = 4 + floor(507 * U**1.95)`` (4..511 tasks, median ~135, mean ~176);
- layered: the number of levels grows like sqrt(n) with a right-skewed factor (the printed critical paths,
  median 41 ms at ~10 ms per task, mean 64 ms, say the DAGs are wide and shallow); every task below the
  first level has a parent in the level above (spread evenly); each non-sink task gets a number of
  children drawn around a per-DAG target out-degree in [0.9, 3.1] that grows with the DAG's size (the
  table's edge count grows faster than its node count), mostly in the next level;
- ``t(v, node) ~ U{1..20}`` ms for every (task, node) pair, keyed by node name; ``d(e) ~ U[1, 5]`` Mbit;
- the cluster: 6 nodes x 2 CPUs, full mesh, each pair's bandwidth ``~ U[500, 1000]`` Mbit/s, no latency.

:func:`dag_stats` measures a corpus the way Table 4.28 reports it (out-degree over non-sink tasks; critical
path = longest path of mean computation costs, no communication). Table 4.28 cannot be matched in full:
a mean out-degree of 1.4 over non-sink tasks allows at most ~1.4 edges per task, while the printed
averages give 305.6 / 181.8 = 1.68 (spec 02 section 12.2 flags it); this generator matches the out-degree
and has fewer edges.
"""

from __future__ import annotations

import math
import random
import statistics
from collections.abc import Iterable
from typing import Any

from continuum.engine.core.cluster import cluster_platform
from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.platform import Platform

__all__ = [
    "COST_MODELS",
    "TABLE_4_28",
    "cluster_doc",
    "corpus_stats",
    "critical_path_length",
    "dag_size",
    "dag_stats",
    "random_cluster",
    "random_dag",
]

#: Table 4.28 as printed: characteristic -> (min, max, avg, median).
TABLE_4_28: dict[str, tuple[float, float, float, float]] = {
    "nodes": (4, 511, 181.8, 130),
    "edges": (3, 1576, 305.6, 158),
    "outdegree": (0.9, 3.1, 1.4, 1.2),
    "critical_path_ms": (4, 446, 64.3, 41),
    "task_cost_ms": (1, 20, 10, 10),
    "edge_data_mbit": (1, 5, 2.5, 2.5),
    "bandwidth_mbps": (500, 1000, 750, 750),
}


def dag_size(rng: random.Random) -> int:
    return 4 + math.floor(507 * rng.random() ** 1.95)


def cluster_doc(rng: random.Random, nodes: int = 6, cores: int = 2) -> dict[str, Any]:
    """A full-mesh ``continuum.cluster/v1`` document with U[500, 1000] Mbit/s links."""
    names = [f"n{i}" for i in range(nodes)]
    return {
        "format": "continuum.cluster/v1",
        "nodes": [{"name": n, "cpu": cores} for n in names],
        "links": [
            {"src": a, "dst": b, "bandwidth_mbps": rng.uniform(500, 1000), "latency_ms": 0.0}
            for i, a in enumerate(names)
            for b in names[i + 1 :]
        ],
    }


def random_cluster(rng: random.Random, nodes: int = 6, cores: int = 2) -> Platform:
    return cluster_platform(cluster_doc(rng, nodes, cores))


COST_MODELS = ("per-node", "per-task")


def random_dag(
    rng: random.Random, nodes: Iterable[str], n: int | None = None, cost_model: str = "per-node"
) -> TaskGraph:
    """One Table 4.28-like DAG whose task costs name ``nodes``.

    ``cost_model="per-node"`` (the spec's reading) draws a cost for every (task, node) pair, unrelated
    machines; ``"per-task"`` draws one cost per task, the same on every node (a homogeneous cluster), a
    sensitivity check since the thesis does not say which it used.
    """
    if cost_model not in COST_MODELS:
        raise ValueError(f"unknown cost model {cost_model!r} (choose from {', '.join(COST_MODELS)})")
    nodes = list(nodes)
    n = dag_size(rng) if n is None else n
    levels = max(2, min(n, round(math.sqrt(n) * (0.1 + 1.4 * rng.random() ** 3))))
    level_of = sorted([*range(levels), *(rng.randrange(levels) for _ in range(n - levels))])
    by_level: list[list[int]] = [[] for _ in range(levels)]
    for i, lv in enumerate(level_of):
        by_level[lv].append(i)
    target = 0.9 + 2.2 * rng.random() ** 2 * (n / 511) ** 0.5
    edges: set[tuple[int, int]] = set()
    children: dict[int, int] = dict.fromkeys(range(n), 0)
    for lv in range(1, levels):  # every task has a parent in the level above, spread evenly
        above = rng.sample(by_level[lv - 1], len(by_level[lv - 1]))
        for k, v in enumerate(rng.sample(by_level[lv], len(by_level[lv]))):
            u = above[k % len(above)]
            edges.add((u, v))
            children[u] += 1
    for lv in range(levels - 1):  # then each non-sink task gets about ``target`` children
        below = by_level[lv + 1]
        deeper = [j for later in by_level[lv + 2 :] for j in later]
        for u in by_level[lv]:
            want = 1 + _poisson(rng, max(0.0, target - 1.0))
            for _ in range(want - children[u]):
                pool = deeper if deeper and rng.random() < 0.15 else below
                v = rng.choice(pool)
                if (u, v) not in edges:
                    edges.add((u, v))
                    children[u] += 1
    if cost_model == "per-node":
        tasks = [{"id": f"t{i}", "cost": {m: rng.randint(1, 20) for m in nodes}} for i in range(n)]
    else:
        tasks = [{"id": f"t{i}", "cost": dict.fromkeys(nodes, rng.randint(1, 20))} for i in range(n)]
    return TaskGraph.from_dict(
        {
            "name": f"table-4.28-{n}",
            "tasks": tasks,
            "edges": [{"src": f"t{u}", "dst": f"t{v}", "data": rng.uniform(1, 5)} for u, v in sorted(edges)],
        }
    )


def _poisson(rng: random.Random, mean: float) -> int:
    # Knuth's method; the means here are small.
    limit, k, p = math.exp(-mean), 0, rng.random()
    while p > limit:
        k += 1
        p *= rng.random()
    return k


def critical_path_length(dag: TaskGraph) -> float:
    """Longest path by mean computation cost over each task's implementations (no communication)."""
    longest: dict[str, float] = {}
    pred = dag.predecessors()
    for tid in dag.topological_order():
        cost = dag.tasks[tid].cost
        mean = sum(cost.values()) / len(cost)
        longest[tid] = mean + max((longest[e.src] for e in pred[tid]), default=0.0)
    return max(longest.values(), default=0.0)


def dag_stats(dag: TaskGraph) -> dict[str, float]:
    """Table 4.28's characteristics of one DAG."""
    sources = {e.src for e in dag.edges}
    return {
        "nodes": len(dag.tasks),
        "edges": len(dag.edges),
        "outdegree": len(dag.edges) / len(sources) if sources else 0.0,
        "critical_path_ms": critical_path_length(dag),
    }


def corpus_stats(dags: Iterable[TaskGraph]) -> dict[str, dict[str, float]]:
    """min/max/avg/median of :func:`dag_stats` (and of costs and data sizes) over a corpus."""
    columns: dict[str, list[float]] = {k: [] for k in ("nodes", "edges", "outdegree", "critical_path_ms")}
    costs: list[float] = []
    data: list[float] = []
    for dag in dags:
        for k, v in dag_stats(dag).items():
            columns[k].append(v)
        costs += [c for t in dag.tasks.values() for c in t.cost.values()]
        data += [e.data for e in dag.edges]
    columns["task_cost_ms"] = costs
    columns["edge_data_mbit"] = data
    return {
        k: {"min": min(v), "max": max(v), "avg": statistics.fmean(v), "median": statistics.median(v)}
        for k, v in columns.items()
        if v
    }
