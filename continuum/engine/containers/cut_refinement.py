"""Cut refinement for ROS-node clustering: k-way Kernighan-Lin / Fiduccia-Mattheyses under a size bound.

Listing 3.20 (:mod:`continuum.engine.containers.ros_clustering`) merges greedily, lowest rank first, so a
node can be merged over its heaviest *free* edge after its heaviest partner was taken: on the path a-b (1),
b-c (100) with 2 containers it returns {a, b}, {c} and leaves the 100 B/s topic between containers while
{a}, {b, c} leaves 1 (issue 27). Peers partition by local search instead:

* Kernighan & Lin, "An efficient heuristic procedure for partitioning graphs", Bell Syst. Tech. J. 49 (1970):
  pair swaps, tentatively applied even at a loss, each node locked once moved, the pass rolled back to its
  best prefix. This lets a pass climb out of a local minimum that one greedy move cannot leave.
* Fiduccia & Mattheyses, "A linear-time heuristic for improving network partitions", DAC 1982: single-node
  moves under a balance bound in the same scheme, extended to k parts (Sanchis 1989).

:func:`refine` runs both kinds of step, k-way, never letting a container grow past ``max_size`` ROS nodes
nor empty, so the container count and the size bound of its start survive. Because a pass keeps only its
best prefix, the cut never grows. :func:`kl_partition` is the peers' baseline: recursive Kernighan-Lin
bisection (networkx) into ``k`` parts of sizes ``floor``/``ceil`` of ``N / k``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from continuum.engine.containers.rosgraph import natural_key

__all__ = ["adjacency", "cut_weight", "kl_partition", "refine"]

Weights = Mapping[tuple[str, str], float]

#: A pass stops after this many steps past its best prefix (FM's usual early exit on large graphs).
PATIENCE = 64
#: Swaps are searched among the best few candidates of each ordered pair of containers.
SWAP_CANDIDATES = 8
EPS = 1e-9


def adjacency(nodes: Sequence[str], weights: Weights) -> dict[str, dict[str, float]]:
    """Symmetric adjacency of positive weights (parallel pairs summed; self-loops and unknown ends ignored)."""
    adj: dict[str, dict[str, float]] = {v: {} for v in nodes}
    for (a, b), w in weights.items():
        if a == b or w <= 0 or a not in adj or b not in adj:
            continue
        adj[a][b] = adj[a].get(b, 0.0) + w
        adj[b][a] = adj[b].get(a, 0.0) + w
    return adj


def cut_weight(weights: Weights, groups: Sequence[Sequence[str]]) -> float:
    """Sum of the weights whose ends lie in different groups (an end in no group counts as cut)."""
    part = {v: i for i, g in enumerate(groups) for v in g}
    return sum(w for (a, b), w in weights.items() if part.get(a) is None or part.get(a) != part.get(b))


def refine(groups: Sequence[Sequence[str]], weights: Weights, max_size: int, max_passes: int = 50) -> list[list[str]]:
    """k-way KL/FM refinement of ``groups``: same number of groups, none empty, none above ``max_size``
    (a group already above it may only shrink), and a cut never larger than the start's."""
    nodes = [v for g in groups for v in g]
    adj = adjacency(nodes, weights)
    part = {v: i for i, g in enumerate(groups) for v in g}
    k = len(groups)
    size = [len(g) for g in groups]
    order = sorted(nodes, key=natural_key)
    for _ in range(max_passes):
        if not _one_pass(order, adj, part, size, k, max_size):
            break
    out: list[list[str]] = [[] for _ in range(k)]
    for v in order:
        out[part[v]].append(v)
    return out


def _conn(v: str, adj: Mapping[str, Mapping[str, float]], part: Mapping[str, int]) -> dict[int, float]:
    c: dict[int, float] = {}
    for u, w in adj[v].items():
        c[part[u]] = c.get(part[u], 0.0) + w
    return c


def _one_pass(
    order: list[str],
    adj: Mapping[str, Mapping[str, float]],
    part: dict[str, int],
    size: list[int],
    k: int,
    max_size: int,
) -> bool:
    """One KL/FM pass; ``part``/``size`` end at the pass's best prefix. True when the cut went down."""
    locked: set[str] = set()
    history: list[list[tuple[str, int]]] = []  # each step: (node, its part before the step)
    gained = best = 0.0
    best_len = 0
    while len(history) - best_len < PATIENCE:
        conn = {v: _conn(v, adj, part) for v in order if v not in locked}
        if not conn:
            break
        step = _best_step(conn, adj, part, size, k, max_size)
        if step is None:
            break
        gain, moves = step
        history.append([(v, part[v]) for v, _ in moves])
        for v, q in moves:
            size[part[v]] -= 1
            size[q] += 1
            part[v] = q
            locked.add(v)
        gained += gain
        if gained > best + EPS:
            best, best_len = gained, len(history)
    for undo in reversed(history[best_len:]):
        for v, p in undo:
            size[part[v]] -= 1
            size[p] += 1
            part[v] = p
    return best > EPS


def _best_step(
    conn: Mapping[str, Mapping[int, float]],
    adj: Mapping[str, Mapping[str, float]],
    part: Mapping[str, int],
    size: Sequence[int],
    k: int,
    max_size: int,
) -> tuple[float, list[tuple[str, int]]] | None:
    """The best single move or pair swap among the unlocked nodes (ties: moves first, then node order)."""
    best: tuple[float, list[tuple[str, int]]] | None = None
    # gain[v][q]: the cut saved by moving v to q (may be negative); by (p, q) the candidates for a swap.
    by_pair: dict[tuple[int, int], list[tuple[float, str]]] = {}
    for v, c in conn.items():
        p = part[v]
        own = c.get(p, 0.0)
        for q in range(k):
            if q == p:
                continue
            g = c.get(q, 0.0) - own
            by_pair.setdefault((p, q), []).append((g, v))
            if size[q] < max_size and size[p] > 1 and (best is None or g > best[0] + EPS):
                best = (g, [(v, q)])
    for (p, q), cands in by_pair.items():
        if p > q or (q, p) not in by_pair:
            continue
        top_pq = sorted(cands, key=lambda t: -t[0])[:SWAP_CANDIDATES]
        top_qp = sorted(by_pair[(q, p)], key=lambda t: -t[0])[:SWAP_CANDIDATES]
        for gu, u in top_pq:
            for gv, v in top_qp:
                g = gu + gv - 2 * adj[u].get(v, 0.0)
                if best is None or g > best[0] + EPS:
                    best = (g, [(u, q), (v, p)])
    return best


def kl_partition(nodes: Sequence[str], weights: Weights, k: int, seed: int = 0) -> list[list[str]]:
    """Recursive Kernighan-Lin bisection (networkx ``kernighan_lin_bisection``) into ``k`` groups whose sizes
    differ by at most one; isolated nodes are partitioned like the others."""
    import networkx as nx

    g = nx.Graph()
    g.add_nodes_from(sorted(nodes, key=natural_key))
    for v, nbrs in adjacency(nodes, weights).items():
        for u, w in nbrs.items():
            g.add_edge(v, u, weight=w)
    return _bisect(g, sorted(nodes, key=natural_key), k, seed)


def _bisect(g: Any, members: list[str], k: int, seed: int) -> list[list[str]]:
    import networkx as nx

    if k <= 1 or len(members) <= 1:
        return [members]
    k1 = k // 2
    n1 = round(len(members) * k1 / k)
    sub = g.subgraph(members)
    # KL swaps pairs, so the start's sizes are kept: n1 and len - n1, in proportion to the parts asked.
    start = (set(members[:n1]), set(members[n1:]))
    x, y = nx.community.kernighan_lin_bisection(sub, partition=start, weight="weight", seed=seed)
    # networkx returns the sides in either order (3.x: the start's second side first); sizes are kept.
    a, b = (x, y) if len(x) == n1 else (y, x)
    a_sorted, b_sorted = sorted(a, key=natural_key), sorted(b, key=natural_key)
    return _bisect(g, a_sorted, k1, seed) + _bisect(g, b_sorted, k - k1, seed)
