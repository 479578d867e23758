"""XEFT: HEFT with clusters of exclusive nodes (thesis 3.1.1, Algorithm 1 ``BuildCluster``, Fig. 3.3).

XEFT rearranges a priority list so that *exclusive* nodes (one implementation only: CPU-only or
GPU-only) that have no path between them sit next to each other, balanced between the CPU cores and the
GPU; phase 2 (processor selection, insertion, tie rules) is HEFT's. The aim is to raise the exclusive
overlap XO(A) (Eq. 3.4) and so cut the idle time that single-implementation nodes cause.

BuildCluster, as spec 01 section 4.1 reads Algorithm 1:
  (a) from an exclusive node ``rank[i]``, collect the later exclusive nodes with no path to or from any
      node collected so far (list order);
  (b) ``total_cpu`` / ``total_gpu``: the sums of the candidates' CPU / GPU times (a missing one counts 0);
  (c) start from the side with the shorter makespan (GPU-only nodes if ``total_gpu < total_cpu/n_cores``,
      else CPU-only nodes) and add the other side's nodes, in list order, while each improves the balance;
  (d) with two or more nodes, make the cluster contiguous with APPLY and go on after it; else go on with
      the next node.
Readings [AMBIGUOUS in the thesis, spec 01 sections 4.1 and 13.3]: row 30 is read as
``|total_cpu/n - (t + g_gpu)|``, mirroring row 22; ``clusterend`` is the list position of the last
cluster node after APPLY; a cluster of 0 or 1 nodes moves on by one; the scan jumps past the cluster even
when ``rank[i]`` itself was left out (``revisit_rejected=True`` moves on by one instead, the prose's
reading); both reachability directions are checked.

APPLY [PROPOSAL of spec 01 section 4.2, checked against all four panels of Fig. 3.3]: with the cluster
members in list order and ``B`` the contiguous block built so far, for each next member ``c``: the nodes
strictly between ``B`` and ``c`` that reach ``c`` stay before it, so the block moves *down* past them;
the others come after ``c``, which moves *up* past them. The list stays a topological order.

A task's CPU (GPU) time is its mean cost over the platform's processors of class ``cpu_class``
(``gpu_class``); ``n_cores`` is the number of ``cpu_class`` processors.
"""

from __future__ import annotations

from collections.abc import Sequence

from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Schedule
from continuum.engine.device.heft import (
    Compiled,
    Progress,
    compile_problem,
    compiled_ranks,
    priority_list,
    schedule_list,
    to_assignments,
)

__all__ = ["apply_cluster", "build_cluster", "class_times", "descendants", "xeft", "xeft_list", "xeft_order"]


def descendants(prob: Compiled) -> list[int]:
    """Per task, a bitset (Python int) of every task reachable from it."""
    desc = [0] * prob.n
    indeg = [len(s) for s in prob.succ]
    stack = [t for t in range(prob.n) if indeg[t] == 0]  # sinks first: reverse topological order
    while stack:
        t = stack.pop()
        bits = 0
        for q, _ in prob.succ[t]:
            bits |= (1 << q) | desc[q]
        desc[t] = bits
        for q, _ in prob.pred[t]:
            indeg[q] -= 1
            if indeg[q] == 0:
                stack.append(q)
    return desc


def class_times(prob: Compiled, cls: str) -> list[float | None]:
    """Per task, its mean time on the processors of class ``cls``; ``None`` without an implementation."""
    procs = prob.platform.processors
    out: list[float | None] = []
    for row in prob.costs:
        times = [c for p, c in row if procs[p].cls == cls]
        out.append(sum(times) / len(times) if times else None)
    return out


def apply_cluster(
    order: list[int], cluster: Sequence[int], desc: Sequence[int], trace: list[list[int]] | None = None
) -> tuple[list[int], int]:
    """Make ``cluster`` contiguous in ``order`` (APPLY); returns the new list and the last member's position.

    ``trace`` collects every intermediate list that differs from the one before (Fig. 3.3's panels).
    """
    where = {t: i for i, t in enumerate(order)}
    members = sorted(cluster, key=where.__getitem__)
    block = [members[0]]
    for c in members[1:]:
        first = order.index(block[0])
        last = first + len(block) - 1
        at = order.index(c)
        between = order[last + 1 : at]
        anc = [s for s in between if desc[s] >> c & 1]
        free = [s for s in between if not desc[s] >> c & 1]
        prefix, suffix = order[:first], order[at + 1 :]
        before = order
        order = prefix + anc + block + [c] + free + suffix  # the block moves down past c's ancestors
        if trace is not None:
            up = prefix + block + anc + [c] + free + suffix  # c moves up past the nodes it does not need
            for step in (up, order):
                if step != (trace[-1] if trace else before):
                    trace.append(step)
        block.append(c)
    return order, order.index(block[-1])


def build_cluster(
    prob: Compiled,
    order: Sequence[int],
    *,
    cpu_class: str = "cpu",
    gpu_class: str = "gpu",
    revisit_rejected: bool = False,
    trace: list[dict] | None = None,
) -> list[int]:
    """Algorithm 1 on a priority list of task indices; returns the rearranged list.

    ``trace`` collects, per cluster formed, the candidates, totals, cluster and APPLY steps.
    """
    rank = list(order)
    n_cores = sum(1 for p in prob.platform.processors if p.cls == cpu_class)
    has_gpu = any(p.cls == gpu_class for p in prob.platform.processors)
    if n_cores == 0 or not has_gpu:
        return rank  # no CPU/GPU pair: nothing can overlap exclusively
    cpu = class_times(prob, cpu_class)
    gpu = class_times(prob, gpu_class)
    classes = [set(prob.classes(t)) for t in range(prob.n)]
    exclusive = [len(c) == 1 and (cpu_class in c or gpu_class in c) for c in classes]
    desc = descendants(prob)
    i = 0
    while i < len(rank):
        if not exclusive[rank[i]]:
            i += 1
            continue
        anchor = rank[i]
        # (a) candidates: exclusive nodes with no path to or from any candidate so far
        cand = [anchor]
        mask = 1 << rank[i]
        below = desc[rank[i]]
        for q in rank[i + 1 :]:
            if exclusive[q] and not (below >> q & 1) and not (desc[q] & mask):
                cand.append(q)
                mask |= 1 << q
                below |= desc[q]
        # (b) the candidates' makespan on each side
        total_cpu = sum(cpu[x] or 0.0 for x in cand)
        total_gpu = sum(gpu[x] or 0.0 for x in cand)
        c_only = [x for x in cand if gpu[x] is None]
        g_only = [x for x in cand if cpu[x] is None]
        # (c) start from the shorter side, add the other side's nodes while the balance improves
        if total_gpu < total_cpu / n_cores:
            cluster = list(g_only)
            t = 0.0
            for c in c_only:
                c_time = cpu[c] or 0.0  # c_only: not None
                if abs(total_gpu - (t + c_time) / n_cores) < abs(total_gpu - t / n_cores):
                    cluster.append(c)
                    t += c_time
        else:
            cluster = list(c_only)
            t = 0.0
            for g in g_only:
                g_time = gpu[g] or 0.0  # g_only: not None
                if abs(total_cpu / n_cores - (t + g_time)) < abs(total_cpu / n_cores - t):
                    cluster.append(g)
                    t += g_time
        # (d) make it contiguous
        if len(cluster) >= 2:
            steps: list[list[int]] | None = [] if trace is not None else None
            rank, end = apply_cluster(rank, cluster, desc, steps)
            if trace is not None:
                trace.append(
                    {
                        "at": i,
                        "candidates": cand,
                        "total_cpu": total_cpu,
                        "total_gpu": total_gpu,
                        "cluster": cluster,
                        "steps": steps,
                    }
                )
            i = i + 1 if revisit_rejected and anchor not in cluster else end + 1
        else:
            i += 1
    return rank


def xeft_order(
    prob: Compiled,
    *,
    rank_mode: str = "max",
    comm_mode: str = "impl",
    cpu_class: str = "cpu",
    gpu_class: str = "gpu",
    revisit_rejected: bool = False,
) -> tuple[list[float], list[int]]:
    """(upward ranks, XEFT priority list) by task index."""
    ranks = compiled_ranks(prob, rank_mode, comm_mode)
    order = build_cluster(
        prob, priority_list(prob, ranks), cpu_class=cpu_class, gpu_class=gpu_class, revisit_rejected=revisit_rejected
    )
    return ranks, order


def xeft(
    dag: TaskGraph,
    platform: Platform,
    *,
    rank_mode: str = "max",
    comm_mode: str = "impl",
    insertion: bool = True,
    cpu_class: str = "cpu",
    gpu_class: str = "gpu",
    revisit_rejected: bool = False,
    progress: Progress | None = None,
) -> Schedule:
    """Schedule ``dag`` on ``platform`` with XEFT (single frame)."""
    prob = compile_problem(dag, platform)
    ranks, order = xeft_order(
        prob,
        rank_mode=rank_mode,
        comm_mode=comm_mode,
        cpu_class=cpu_class,
        gpu_class=gpu_class,
        revisit_rejected=revisit_rejected,
    )
    placed = schedule_list(prob, order, insertion=insertion, progress=progress)
    return Schedule(
        "xeft",
        to_assignments(prob, placed),
        ranks=dict(zip(prob.ids, ranks, strict=True)),
        params={"rank_mode": rank_mode, "comm_mode": comm_mode, "insertion": insertion},
        metrics={"priority_list": [prob.ids[t] for t in order]},
    )


def xeft_list(dag: TaskGraph, platform: Platform, order: Sequence[str], **kwargs) -> list[str]:
    """BuildCluster on any priority list of task ids (a topological order); returns the new list of ids."""
    prob = compile_problem(dag, platform)
    index = {tid: i for i, tid in enumerate(prob.ids)}
    return [prob.ids[t] for t in build_cluster(prob, [index[t] for t in order], **kwargs)]
