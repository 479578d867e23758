"""Clustering ROS nodes into containers: thesis Section 3.2.1, Listing 3.20, Definition 3.2.1, Eq. (3.13).

The algorithm is adapted from hierarchical agglomerative clustering with *sum* linkage: the weight between
two clusters is the sum of the bandwidths (Eq. 3.12) of the ROS-node pairs across them (Definition 3.2.1),
and intra-cluster edges disappear. Listing 3.20 as the spec (02, section 2.5) cleans it up:

1. ROS nodes without edges are set aside first ("culled"): they can join any container at no bandwidth cost.
2. While more than ``n`` cluster vertices remain, one pass visits the vertices lowest rank first (rank =
   number of ROS nodes inside), ties in natural name order (``v2 < v10``); each unused vertex merges with
   its unused neighbour over the heaviest edge (ties: lower rank, then name), or is copied unmerged when
   every neighbour is used. The vertex count is checked after every vertex, so a pass stops merging as soon
   as the count can reach ``n``; the remaining vertices are copied unchanged.
3. Guard (the spec's proposal): a pass that merges nothing ends the loop, so disconnected components that
   cannot merge return more than ``n`` clusters (reported in ``guard_fired``) instead of looping forever.

Listing bugs the spec tells us to ignore: line 10 as printed loops forever; line 11's "used" test belongs
before line 8; the candidate must differ from the vertex itself.

After clustering (spec proposals, both parameters): culled nodes join a cluster of the same context when
one exists, else the cluster with the lowest resource demand; and the resource tie-breaker of Section
3.2.1 (Figs. 3.22-3.23) splits resource-heavy ROS nodes out of a cluster that holds more than
``max_cluster_share`` of all ROS nodes or more than ``max_cluster_memory_mib``. The spec proposes a share of
0.5; we leave it off by default so that ``cluster_ros --containers N`` returns N containers when it can.

Two methods (``method``; the deployment's default is ``settings.CONTINUUM_ROS_CLUSTERING``):

* ``"thesis"``: Listing 3.20 as above, nothing more.
* ``"refined"`` (the default): Listing 3.20, then k-way Kernighan-Lin/Fiduccia-Mattheyses refinement
  (:mod:`continuum.engine.containers.cut_refinement`) under the same bound on a container's ROS-node count
  as Listing 3.20's own result (its largest container), started both from Listing 3.20's containers and from
  recursive Kernighan-Lin bisection; the lower cut wins (Listing 3.20's on a tie). Listing 3.20 greedily
  merges over the heaviest *free* edge, so it can leave the heaviest topic between containers (issue 27:
  path a-b (1), b-c (100), 2 containers gives {a, b}, {c}, cut 100, where {a}, {b, c} cuts 1); the refined
  method never cuts more than Listing 3.20 nor than Kernighan-Lin under that bound.

Eq. (3.13) bounds the container count: ``n <= floor(available memory / per-container overhead)``
(:func:`max_containers`; seed overheads: 29 MB Docker and ~39 MB K3s per container, Table 4.17).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from continuum.engine.containers.cut_refinement import cut_weight, kl_partition, refine
from continuum.engine.containers.rosgraph import RosGraph, natural_key, pair
from continuum.engine.core.errors import InputError

__all__ = [
    "METHODS",
    "OVERHEAD_MIB",
    "Clustering",
    "Container",
    "cluster_nodes",
    "cluster_ros",
    "max_containers",
    "split_bandwidth",
    "split_heavy_nodes",
]

#: Clustering methods: Listing 3.20 then KL/FM refinement (the default), or Listing 3.20 alone.
METHODS = ("refined", "thesis")

#: Measured per-container memory overheads (MiB) that can seed Eq. (3.13).
OVERHEAD_MIB = {"docker": 29.0, "k3s": 39.0, "runc-riscv": 1.9}


def max_containers(available_mib: float, overhead_mib: float) -> int:
    """Eq. (3.13): ``floor(available_system_memory / container_overhead)``; a bound below 1 is an error."""
    if not (isinstance(overhead_mib, (int, float)) and overhead_mib > 0 and math.isfinite(overhead_mib)):
        raise InputError(f"container overhead must be a positive number of MiB, got {overhead_mib!r}", "overhead")
    if not (isinstance(available_mib, (int, float)) and available_mib >= 0 and math.isfinite(available_mib)):
        raise InputError(f"available memory must be a non-negative number of MiB, got {available_mib!r}", "memory")
    ratio = available_mib / overhead_mib
    if not math.isfinite(ratio):  # 1e308 MiB / 1e-308 MiB: no integer bound
        raise InputError(
            f"Eq. 3.13: {available_mib:g} / {overhead_mib:g} is not a finite number of containers", "memory"
        )
    bound = math.floor(ratio + 1e-9)
    if bound < 1:
        raise InputError(
            f"Eq. 3.13: {available_mib:g} MiB of memory cannot hold one container of {overhead_mib:g} MiB overhead",
            "memory",
        )
    return bound


@dataclass(frozen=True)
class Container:
    name: str
    nodes: tuple[str, ...]

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "nodes": list(self.nodes)}


@dataclass
class Clustering:
    """Result of :func:`cluster_nodes` / :func:`cluster_ros` (the ``cluster_ros`` contract keys + history)."""

    containers: list[Container]
    culled: list[str]
    #: After each merging pass: ``{"clusters": [[members]], "edges": [[a, b, weight]]}`` with clusters named
    #: by their smallest member, for a Fig. 3.21-style animation.
    passes: list[dict[str, Any]]
    requested: int
    guard_fired: bool = False
    inter_container_bandwidth: float = 0.0
    intra_container_bandwidth: float = 0.0
    #: ROS nodes pulled into containers of their own by the resource tie-breaker.
    split_off: list[str] = field(default_factory=list)
    params: dict[str, Any] = field(default_factory=dict)

    def assignment(self) -> dict[str, str]:
        """ROS node -> container name."""
        return {n: c.name for c in self.containers for n in c.nodes}

    def to_dict(self) -> dict[str, Any]:
        return {
            "containers": [c.to_dict() for c in self.containers],
            "inter_container_bandwidth": self.inter_container_bandwidth,
            "intra_container_bandwidth": self.intra_container_bandwidth,
            "requested_containers": self.requested,
            "culled": list(self.culled),
            "guard_fired": self.guard_fired,
            "split_off": list(self.split_off),
            "passes": [{"clusters": [list(c) for c in p["clusters"]], "edges": list(p["edges"])} for p in self.passes],
            "params": dict(self.params),
        }


# ---- Listing 3.20 ---------------------------------------------------------------------------------
def cluster_nodes(
    nodes: Sequence[str], weights: Mapping[tuple[str, str], float], n: int, max_passes: int | None = None
) -> Clustering:
    """Listing 3.20 on an undirected weighted graph; culled nodes are returned apart, not attached.

    ``weights`` maps a pair of node names (either order) to its bandwidth; pairs with weight 0 count as no
    edge (merging over them saves nothing).
    """
    if not isinstance(n, int) or isinstance(n, bool) or n < 1:
        raise InputError(f"the number of containers must be a positive integer, got {n!r}", "containers")
    known = set(nodes)
    if len(known) != len(nodes):
        raise InputError("duplicate ROS node names", "nodes")
    adj: dict[str, dict[str, float]] = {v: {} for v in nodes}
    for (a, b), w in weights.items():
        for end in (a, b):
            if end not in known:
                raise InputError(f"edge {a}-{b} refers to unknown ROS node {end!r}", "edges")
        if not (isinstance(w, (int, float)) and math.isfinite(w) and w >= 0):
            raise InputError(f"edge {a}-{b} has invalid bandwidth {w!r}", "edges")
        if a == b or w == 0:
            continue
        adj[a][b] = adj[a].get(b, 0.0) + w
        adj[b][a] = adj[b].get(a, 0.0) + w

    culled = sorted((v for v in nodes if not adj[v]), key=natural_key)  # line 2
    members: dict[str, list[str]] = {v: [v] for v in nodes if adj[v]}
    for v in culled:
        del adj[v]
    passes: list[dict[str, Any]] = []
    guard = False
    while len(members) > n:  # line 3
        if max_passes is not None and len(passes) >= max_passes:
            break
        new_members, new_adj, merged = _one_pass(members, adj, n)
        if not merged:
            guard = True
            break
        members, adj = new_members, new_adj
        passes.append(_snapshot(members, adj))
    containers = [Container(name, tuple(ms)) for name, ms in _ordered_items(members)]
    return Clustering(containers, culled, passes, n, guard_fired=guard)


def _rank_key(members: Mapping[str, list[str]], v: str) -> tuple:
    return (len(members[v]), natural_key(v))


def _snapshot(members: Mapping[str, list[str]], adj: Mapping[str, Mapping[str, float]]) -> dict[str, Any]:
    """One pass's outcome: the clusters and the Def. 3.2.1 weights between them (named by smallest member)."""
    edges = sorted(
        ((a, b, w) for a, nbrs in adj.items() for b, w in nbrs.items() if natural_key(a) < natural_key(b)),
        key=lambda e: (natural_key(e[0]), natural_key(e[1])),
    )
    return {"clusters": [list(ms) for _, ms in _ordered_items(members)], "edges": [list(e) for e in edges]}


def _ordered_items(members: Mapping[str, list[str]]) -> list[tuple[str, list[str]]]:
    return sorted(members.items(), key=lambda kv: natural_key(kv[0]))


def _one_pass(
    members: dict[str, list[str]], adj: dict[str, dict[str, float]], n: int
) -> tuple[dict[str, list[str]], dict[str, dict[str, float]], bool]:
    order = sorted(members, key=lambda v: _rank_key(members, v))  # line 4
    used: set[str] = set()
    groups: list[list[str]] = []  # each new vertex = list of old vertices
    stop = False
    merged = False
    for idx, v in enumerate(order):  # line 7
        if v in used:  # line 11, tested first
            continue
        if stop:
            groups.append([v])
            used.add(v)
            continue
        free = [u for u in adj[v] if u not in used and u != v]  # lines 8-10
        if free:
            cand = min(free, key=lambda u: (-adj[v][u], *_rank_key(members, u)))
            groups.append([v, cand])
            used.update((v, cand))
            merged = True
        else:
            groups.append([v])
            used.add(v)
        remaining = sum(1 for w in order[idx + 1 :] if w not in used)
        if len(groups) + remaining <= n:
            stop = True
    return (*_refactor(members, adj, groups), merged)


def _refactor(
    members: Mapping[str, list[str]], adj: Mapping[str, Mapping[str, float]], groups: Iterable[list[str]]
) -> tuple[dict[str, list[str]], dict[str, dict[str, float]]]:
    """Merge each group into one vertex named after its smallest member; sum parallel edges (Def. 3.2.1)."""
    new_members: dict[str, list[str]] = {}
    owner: dict[str, str] = {}
    for group in groups:
        ms = sorted((m for v in group for m in members[v]), key=natural_key)
        new_members[ms[0]] = ms
        for v in group:
            owner[v] = ms[0]
    new_adj: dict[str, dict[str, float]] = {v: {} for v in new_members}
    for v, nbrs in adj.items():
        for u, w in nbrs.items():
            a, b = owner[v], owner[u]
            if a != b:  # intra-cluster edges disappear
                new_adj[a][b] = new_adj[a].get(b, 0.0) + w
    # Each undirected edge was visited from both ends, so both directions hold the full sum already.
    return new_members, new_adj


# ---- the full pipeline on a ROS graph -------------------------------------------------------------
def cluster_ros(
    graph: RosGraph,
    n: int,
    *,
    mode: str = "per_topic",
    available_mib: float | None = None,
    overhead_mib: float | None = None,
    max_cluster_share: float | None = None,
    max_cluster_memory_mib: float | None = None,
    method: str = "refined",
) -> Clustering:
    """Cluster a ROS graph into at most ``n`` containers and account for the bandwidth left between them.

    With ``available_mib`` and ``overhead_mib``, ``n`` is checked against Eq. (3.13). ``method`` is one of
    :data:`METHODS` (module docstring).
    """
    if method not in METHODS:
        raise InputError(f"unknown clustering method {method!r} (one of {', '.join(METHODS)})", "method")
    params: dict[str, Any] = {"mode": mode, "containers": n, "method": method}
    if available_mib is not None or overhead_mib is not None:
        if available_mib is None or overhead_mib is None:
            raise InputError("Eq. 3.13 needs both the available memory and the per-container overhead", "memory")
        bound = max_containers(available_mib, overhead_mib)
        params["eq_3_13_bound"] = bound
        if n > bound:
            raise InputError(
                f"{n} containers exceed the Eq. 3.13 bound floor({available_mib:g} / {overhead_mib:g}) = {bound}",
                "containers",
            )
    weights = graph.weights(mode)
    nodes = sorted(graph.nodes, key=natural_key)
    result = cluster_nodes(nodes, weights, n)
    groups = {c.name: list(c.nodes) for c in result.containers}
    _attach_culled(graph, groups, result.culled, n)
    if method == "refined":
        groups = refined_groups(groups, weights)
    split: list[str] = []
    if max_cluster_share is not None or max_cluster_memory_mib is not None:
        split = split_heavy_nodes(graph, groups, weights, max_cluster_share, max_cluster_memory_mib)
        params.update(max_cluster_share=max_cluster_share, max_cluster_memory_mib=max_cluster_memory_mib)
    result.containers = [
        Container(ms[0], tuple(ms))
        for ms in sorted((sorted(g, key=natural_key) for g in groups.values() if g), key=lambda m: natural_key(m[0]))
    ]
    result.split_off = split
    result.inter_container_bandwidth, result.intra_container_bandwidth = split_bandwidth(weights, result.assignment())
    result.params = params
    return result


def refined_groups(groups: Mapping[str, list[str]], weights: Mapping[tuple[str, str], float]) -> dict[str, list[str]]:
    """Listing 3.20's ``groups`` refined (module docstring): the same count, no container above the largest
    of ``groups``, the lower cut of the refinements started from ``groups`` and from Kernighan-Lin."""
    start = [list(ms) for _, ms in sorted(groups.items(), key=lambda kv: natural_key(kv[0])) if ms]
    if len(start) < 2:
        return {k: list(v) for k, v in groups.items()}
    bound = max(len(g) for g in start)
    nodes = [v for g in start for v in g]
    candidates = [refine(start, weights, bound), refine(kl_partition(nodes, weights, len(start)), weights, bound)]
    best = min(candidates, key=lambda gs: cut_weight(weights, gs) - 1e-9 * (gs is candidates[0]))
    if cut_weight(weights, best) >= cut_weight(weights, start) - 1e-9:
        return {k: list(v) for k, v in groups.items()}
    return {sorted(g, key=natural_key)[0]: sorted(g, key=natural_key) for g in best if g}


def split_bandwidth(weights: Mapping[tuple[str, str], float], assignment: Mapping[str, str]) -> tuple[float, float]:
    """(inter, intra) bandwidth of a grouping: the sum of edge weights across groups and inside them."""
    inter = intra = 0.0
    for (a, b), w in weights.items():
        if assignment.get(a) is not None and assignment.get(a) == assignment.get(b):
            intra += w
        else:
            inter += w
    return inter, intra


def _demand(graph: RosGraph, members: Iterable[str]) -> tuple[float, float]:
    ms = list(members)
    return (sum(graph.nodes[m].cpu for m in ms), sum(graph.nodes[m].memory_mib for m in ms))


def _attach_culled(graph: RosGraph, groups: dict[str, list[str]], culled: Sequence[str], n: int) -> None:
    """Culled ROS nodes join a cluster of their context, else the cluster of lowest resource demand
    (CPU, then memory, then size, then name). With no clusters at all, up to ``n`` containers are opened."""
    if not culled:
        return
    if not groups:
        for v in sorted(culled, key=lambda m: (-graph.nodes[m].cpu, -graph.nodes[m].memory_mib, natural_key(m))):
            if len(groups) < n:
                groups[v] = [v]
            else:
                target = min(groups, key=lambda g: (*_demand(graph, groups[g]), len(groups[g]), natural_key(g)))
                groups[target].append(v)
        return
    for v in culled:
        context = graph.nodes[v].context
        same = [g for g, ms in groups.items() if context and any(graph.nodes[m].context == context for m in ms)]
        pool = same or list(groups)
        target = min(pool, key=lambda g: (*_demand(graph, groups[g]), len(groups[g]), natural_key(g)))
        groups[target].append(v)


def split_heavy_nodes(
    graph: RosGraph,
    groups: dict[str, list[str]],
    weights: Mapping[tuple[str, str], float],
    max_share: float | None,
    max_memory_mib: float | None,
) -> list[str]:
    """The resource tie-breaker (Figs. 3.22-3.23): pull the heaviest ROS node out of every over-large cluster
    into a container of its own, one by one, until no cluster exceeds the share or memory cap. "Heaviest" is
    by memory then CPU over the memory cap, by CPU then memory over the share cap; ties go to the node whose
    departure costs the least bandwidth (the communication cost is unavoidable, so keep it small), then to
    the first name. Returns the split nodes in order."""
    if max_share is not None and not (0 < max_share <= 1):
        raise InputError(f"max cluster share must lie in (0, 1], got {max_share!r}", "max_cluster_share")
    if max_memory_mib is not None and not (max_memory_mib > 0):
        raise InputError(f"max cluster memory must be positive, got {max_memory_mib!r}", "max_cluster_memory_mib")
    total = sum(len(ms) for ms in groups.values())
    split: list[str] = []

    def too_big(ms: list[str]) -> str | None:
        """Which cap the cluster breaks ("memory" first, then "share"), if any."""
        if len(ms) <= 1:
            return None
        if max_memory_mib is not None and _demand(graph, ms)[1] > max_memory_mib:
            return "memory"
        if max_share is not None and len(ms) > max_share * total:
            return "share"
        return None

    changed = True
    while changed:
        changed = False
        for name in sorted(groups, key=natural_key):
            ms = groups[name]
            broken = too_big(ms)
            if broken is None:
                continue

            def cut(v: str, ms: list[str] = ms) -> float:
                return sum(weights.get(pair(v, u), 0.0) for u in ms if u != v)

            def weight(v: str, broken: str = broken) -> tuple[float, float]:
                cpu, mem = graph.nodes[v].cpu, graph.nodes[v].memory_mib
                return (mem, cpu) if broken == "memory" else (cpu, mem)

            heaviest = min(ms, key=lambda v: (-weight(v)[0], -weight(v)[1], cut(v), natural_key(v)))
            ms.remove(heaviest)
            groups[heaviest if heaviest not in groups else f"{heaviest}#split"] = [heaviest]
            split.append(heaviest)
            changed = True
            break
    return split
