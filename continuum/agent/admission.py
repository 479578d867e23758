"""How much deadline bandwidth this node's kernel admits: what RT-Kube's filter must not exceed.

The kernel admits a new deadline task on a root domain while the bandwidths (runtime/period) of its deadline
tasks stay within ``M x sched_rt_runtime_us / sched_rt_period_us`` (M: the domain's CPUs). Since Linux 6.12 each
CPU's fair server (the reservation that keeps SCHED_OTHER alive under real-time load) is a deadline entity in
that sum too: 50 ms per 1 s by default, so one CPU admits about 0.90, not the 0.95 RT-Kube assumed (measured
here: 0.899). Read in this order:

1. ``/proc/sys/kernel/sched_rt_runtime_us`` and ``sched_rt_period_us`` (``-1``: no limit, 1.0 per CPU);
2. each CPU's fair server, ``/sys/kernel/debug/sched/fair_server/cpuN/{runtime,period}`` (nanoseconds), when
   debugfs is mounted and readable;
3. otherwise, on a kernel that has a fair server (>= 6.12) or when asked (``probe=True``), a probe: deadline
   tasks are admitted one after another in this process's root domain (each a forked child that asks for
   SCHED_DEADLINE for itself and then sleeps, holding its bandwidth), the last one's bandwidth found by
   bisection to 0.001; the sum is what the kernel admitted. A probe measures what is free *now*: run it before
   the node's RT pods start (it says so in ``source``).

The CPUs are this process's affinity, which for a deadline task must be its whole root domain (a node's exclusive
cpuset). Standard library only, as the rest of the agent.
"""

from __future__ import annotations

import contextlib
import os
import platform
import re
import signal
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from .sched import DeadlineParams, set_deadline

FAIR_SERVER = Path("/sys/kernel/debug/sched/fair_server")
PROC = Path("/proc/sys/kernel")
#: The kernel release from which each CPU has a fair server (a deadline server in the admission's sum).
FAIR_SERVER_SINCE = (6, 12)
PROBE_PERIOD_NS = 10_000_000
PROBE_STEP = 0.001


@dataclass
class Admission:
    """A node's admissible deadline bandwidth (in CPUs) and how it was found."""

    capacity: float
    cpus: list[int]
    source: str
    kernel: str = field(default_factory=platform.release)
    rt_runtime_us: int | None = None
    rt_period_us: int | None = None
    fair_server: dict[str, float] | None = None  # per CPU: the fair server's bandwidth, where read
    probed: float | None = None

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def kernel_version(release: str | None = None) -> tuple[int, int]:
    match = re.match(r"(\d+)\.(\d+)", release or platform.release())
    return (int(match.group(1)), int(match.group(2))) if match else (0, 0)


def _read_int(path: Path) -> int | None:
    try:
        return int(path.read_text().strip())
    except (OSError, ValueError):
        return None


def fair_servers(cpus: list[int], root: Path = FAIR_SERVER) -> dict[str, float] | None:
    """Each CPU's fair-server bandwidth (runtime / period), or None when they cannot all be read."""
    out = {}
    for cpu in cpus:
        runtime, period = _read_int(root / f"cpu{cpu}" / "runtime"), _read_int(root / f"cpu{cpu}" / "period")
        if runtime is None or not period:
            return None
        out[str(cpu)] = runtime / period
    return out


def hold_reservation(params: DeadlineParams, before: Callable[[], object] | None = None) -> int | None:
    """A child that is a deadline task of ``params`` (after ``before``, e.g. joining a cgroup), asleep until killed:
    its pid, or None if the kernel refused it (the child has then exited)."""
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: ask for the bandwidth, say whether it got it, then hold it (asleep) until killed
        code = 1
        try:
            os.close(r)
            signal.signal(signal.SIGINT, signal.SIG_DFL)
            if before is not None:
                before()
            set_deadline(params, flags=0)
            os.write(w, b"y")
            os.close(w)
            code = 0
            while True:
                signal.pause()  # asleep, the bandwidth still reserved
        except OSError:
            pass
        finally:
            os._exit(code)
    os.close(w)
    got = os.read(r, 1)
    os.close(r)
    if got == b"y":
        return pid
    os.waitpid(pid, 0)
    return None


def _admit_and_hold(bandwidth: float) -> int | None:
    return hold_reservation(DeadlineParams(max(1024, round(bandwidth * PROBE_PERIOD_NS)), PROBE_PERIOD_NS,
                                           PROBE_PERIOD_NS))  # fmt: skip


def _release(pid: int) -> None:
    with contextlib.suppress(ProcessLookupError):
        os.kill(pid, signal.SIGKILL)
    os.waitpid(pid, 0)


def probe(step: float = PROBE_STEP, limit: int = 1024) -> float:
    """The deadline bandwidth the kernel admits now in this process's root domain (see the module docstring)."""
    held: list[int] = []
    total = 0.0
    try:
        while len(held) < limit:
            full = _admit_and_hold(1.0)
            if full is not None:
                held.append(full)
                total += 1.0
                continue
            lo, hi = 0.0, 1.0
            while hi - lo > step:
                mid = (lo + hi) / 2
                got = _admit_and_hold(mid)
                if got is not None:
                    _release(got)
                    lo = mid
                else:
                    hi = mid
            return total + lo
        return total
    finally:
        for pid in held:
            _release(pid)
        # A killed deadline task's bandwidth comes back at its 0-lag time (within its period), not at its death:
        # what was measured is free again only then.
        time.sleep(2 * PROBE_PERIOD_NS / 1e9)


def measure(use_probe: bool = False, cpus: list[int] | None = None) -> Admission:
    """This node's admission (``use_probe``: always probe, as a check of the computed figure)."""
    cpus = sorted(cpus if cpus is not None else os.sched_getaffinity(0))
    runtime, period = _read_int(PROC / "sched_rt_runtime_us"), _read_int(PROC / "sched_rt_period_us")
    if runtime is None or not period:
        ratio, what = 0.95, "sched_rt_* unreadable: the thesis' 0.95 per CPU"
    elif runtime < 0:
        ratio, what = 1.0, "sched_rt_runtime_us -1 (no limit)"
    else:
        ratio, what = runtime / period, f"sched_rt_runtime_us/period {runtime}/{period}"
    fair = fair_servers(cpus)
    result = Admission(len(cpus) * ratio, cpus, what, rt_runtime_us=runtime, rt_period_us=period, fair_server=fair)
    has_fair_server = kernel_version() >= FAIR_SERVER_SINCE
    if fair is not None:
        result.capacity -= sum(fair.values())
        result.source += " less the fair servers (debugfs)"
    if use_probe or (fair is None and has_fair_server):
        result.probed = probe()
        result.capacity = result.probed
        reason = "asked" if use_probe else f"kernel {platform.release()} has a fair server, debugfs not readable"
        result.source = f"probe of the kernel's admission ({reason}; what was free at the time)"
    result.capacity = round(result.capacity, 4)
    return result
