"""SCHED_DEADLINE through ``sched_setattr(2)`` (ctypes, no dependency): the parameters, the call, its errors.

The Python standard library has ``os.sched_setscheduler`` but no ``sched_setattr``, the only call that sets a
deadline task's runtime, deadline and period. Times are nanoseconds in the kernel's ``struct sched_attr``.
"""

from __future__ import annotations

import ctypes
import errno
import os
import platform
from dataclasses import dataclass
from pathlib import Path

SCHED_DEADLINE = 6
#: A child forked by the deadline task starts as SCHED_OTHER (without it, fork() fails with EAGAIN).
SCHED_FLAG_RESET_ON_FORK = 0x01
#: Every runtime overrun sends SIGXCPU to the task (Linux >= 4.16).
SCHED_FLAG_DL_OVERRUN = 0x04

#: sched_setattr's number per architecture (asm-generic for the newer ports).
_SYSCALL = {"x86_64": 314, "aarch64": 274, "arm64": 274, "armv7l": 380, "armv6l": 380, "i686": 351, "i386": 351,
            "riscv64": 274, "ppc64le": 355, "s390x": 345}  # fmt: skip

#: The kernel's limits on the parameters (kernel/sched/deadline.c, __checkparam_dl).
MIN_RUNTIME_NS = 1 << 10


class _SchedAttr(ctypes.Structure):
    _fields_ = [
        ("size", ctypes.c_uint32),
        ("sched_policy", ctypes.c_uint32),
        ("sched_flags", ctypes.c_uint64),
        ("sched_nice", ctypes.c_int32),
        ("sched_priority", ctypes.c_uint32),
        ("sched_runtime", ctypes.c_uint64),
        ("sched_deadline", ctypes.c_uint64),
        ("sched_period", ctypes.c_uint64),
    ]


@dataclass(frozen=True)
class DeadlineParams:
    """A RealTime resource's timing on one node: runtime (the node's WCET), deadline, period, in nanoseconds."""

    runtime_ns: int
    deadline_ns: int
    period_ns: int

    @classmethod
    def from_ms(cls, runtime_ms: float, deadline_ms: float, period_ms: float) -> DeadlineParams:
        return cls(round(runtime_ms * 1e6), round(deadline_ms * 1e6), round(period_ms * 1e6))

    @property
    def bandwidth(self) -> float:
        """What the kernel's admission adds up: runtime / period (Eq. 2.4 uses the period, as the kernel does)."""
        return self.runtime_ns / self.period_ns

    def problem(self) -> str | None:
        """Why the kernel would refuse these values with EINVAL, in words (None: they are valid)."""
        r, d, p = self.runtime_ns, self.deadline_ns, self.period_ns
        if r < MIN_RUNTIME_NS:
            return f"runtime must be at least {MIN_RUNTIME_NS} ns (got {r} ns)"
        if not r <= d <= p:
            return f"need runtime <= deadline <= period (got {r / 1e6:g} / {d / 1e6:g} / {p / 1e6:g} ms)"
        lo, hi = period_limits_us()
        if not lo * 1000 <= p <= hi * 1000:
            return f"period must be within {lo / 1000:g}..{hi / 1000:g} ms (kernel.sched_deadline_period_*_us)"
        if p >= 1 << 63:
            return "period too large"
        return None


def period_limits_us() -> tuple[int, int]:
    """``kernel.sched_deadline_period_min_us`` / ``max_us`` (defaults 100 us and 2^22 us where not exposed)."""
    out = []
    for name, default in (("min", 100), ("max", 1 << 22)):
        try:
            out.append(int(Path(f"/proc/sys/kernel/sched_deadline_period_{name}_us").read_text()))
        except (OSError, ValueError):
            out.append(default)
    return out[0], out[1]


def rt_bandwidth() -> float | None:
    """The share of each CPU deadline and FIFO tasks may take: sched_rt_runtime_us / sched_rt_period_us."""
    try:
        runtime = int(Path("/proc/sys/kernel/sched_rt_runtime_us").read_text())
        period = int(Path("/proc/sys/kernel/sched_rt_period_us").read_text())
    except (OSError, ValueError):
        return None
    return None if runtime < 0 else runtime / period


_libc = ctypes.CDLL(None, use_errno=True)


def set_deadline(params: DeadlineParams, pid: int = 0, flags: int = SCHED_FLAG_DL_OVERRUN | SCHED_FLAG_RESET_ON_FORK
                 ) -> None:  # fmt: skip
    """Make ``pid`` (0: the caller) a SCHED_DEADLINE task; raises OSError with the kernel's errno."""
    number = _SYSCALL.get(platform.machine())
    if number is None:
        raise OSError(errno.ENOSYS, f"sched_setattr: unknown system call number on {platform.machine()}")
    attr = _SchedAttr(ctypes.sizeof(_SchedAttr), SCHED_DEADLINE, flags, 0, 0,
                      params.runtime_ns, params.deadline_ns, params.period_ns)  # fmt: skip
    if _libc.syscall(ctypes.c_long(number), ctypes.c_int(pid), ctypes.byref(attr), ctypes.c_uint(0)) != 0:
        code = ctypes.get_errno()
        raise OSError(code, os.strerror(code))


#: What each errno of sched_setattr means for a deadline task, and the agent's exit status for it.
REFUSALS = {
    errno.EBUSY: (
        75,
        "the kernel refused the deadline task: admission control, the deadline bandwidth of its root "
        "domain's CPUs (sched_rt_runtime_us/sched_rt_period_us each, less the fair server's share on "
        "Linux >= 6.12) is taken",
    ),
    errno.EPERM: (
        77,
        "not permitted to set SCHED_DEADLINE: needs root or CAP_SYS_NICE, a CPU affinity that "
        "covers its whole root domain (cpuset), and RT bandwidth in its cgroup",
    ),
    errno.EINVAL: (
        69,
        "the kernel rejected the deadline parameters (SCHED_DEADLINE unsupported or values out of its limits)",
    ),
    errno.ENOSYS: (69, "this kernel has no sched_setattr (SCHED_DEADLINE needs Linux >= 3.14)"),
    errno.E2BIG: (69, "this kernel does not know the sched_attr layout (SCHED_FLAG_DL_OVERRUN needs Linux >= 4.16)"),
}


def refusal(code: int) -> tuple[int, str]:
    """(exit status, reason) for a failed sched_setattr."""
    return REFUSALS.get(code, (69, f"sched_setattr failed: {os.strerror(code)}"))
