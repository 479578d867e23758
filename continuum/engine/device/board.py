"""The CPU + integrated-GPU board of the thesis' device-level scheduling (spec 01 section 1, Table 2.1).

A board has ``n_cores`` CPU cores and one (or more) GPUs sharing one physical memory. Expressed with the
``continuum.platform/v1`` contract:

- processors ``cpu0 .. cpu{n-1}`` of class ``cpu`` (listed first, so processor ties go to the CPU and to
  the lowest core, spec 01 section 2.3), then ``gpu0 ..`` of class ``gpu``;
- ``speed`` per core models the TX2's Denver and A57 clusters ("inter-cluster mapping", Table 2.1): a
  class cost ``t`` takes ``t / speed`` on that core [PROPOSAL of spec 01 section 1];
- transfers between CPU cores are free (shared memory): a link with ``bandwidth: null`` between every pair
  of cores; a CPU <-> GPU transfer of an edge with ``data = transfer_ms`` takes ``transfer_ms`` (platform
  bandwidth 1, latency 0), or nothing with ``transfer=False``.
"""

from __future__ import annotations

from collections.abc import Sequence

from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Link, Platform, Processor

__all__ = ["board", "shared_memory"]


def board(
    n_cores: int,
    n_gpus: int = 1,
    *,
    cpu_speed: Sequence[float] | None = None,
    transfer: bool = True,
) -> Platform:
    """A board with ``n_cores`` CPU cores (optional per-core speeds) and ``n_gpus`` GPUs."""
    if n_cores < 0 or n_gpus < 0 or n_cores + n_gpus == 0:
        raise InputError("a board needs at least one CPU core or GPU", "processors")
    speeds = list(cpu_speed) if cpu_speed is not None else [1.0] * n_cores
    if len(speeds) != n_cores:
        raise InputError(f"cpu_speed has {len(speeds)} values for {n_cores} cores", "cpu_speed")
    procs = [Processor(f"cpu{i}", "cpu", float(s)) for i, s in enumerate(speeds)]
    procs += [Processor(f"gpu{i}", "gpu") for i in range(n_gpus)]
    cores = [p.id for p in procs if p.cls == "cpu"]
    gpus = [p.id for p in procs if p.cls == "gpu"]
    # GPUs of one board share the memory too; only CPU <-> GPU moves cost.
    links = [Link(a, b, None) for group in (cores, gpus) for i, a in enumerate(group) for b in group[i + 1 :]]
    return Platform(procs, bandwidth=1.0 if transfer else None, latency=0.0, links=links)


def shared_memory(platform: Platform) -> Platform:
    """``platform`` with free transfers between processors of the same class (a shared-memory device)."""
    by_class: dict[str, list[str]] = {}
    for p in platform.processors:
        by_class.setdefault(p.cls, []).append(p.id)
    extra = [Link(a, b, None) for group in by_class.values() for i, a in enumerate(group) for b in group[i + 1 :]]
    return Platform(
        list(platform.processors),
        bandwidth=platform.bandwidth,
        latency=platform.latency,
        links=[*platform.links, *extra],
        route=platform.route,
    )
