"""CPU and memory of a ROS node's process from ``/proc``, when the node runs on this machine.

A pid that a node reports (``getPid``) names a process in the node's pid namespace: on another host, or in a
container, the same number may be another process here. :func:`owns_port` checks that the process at ``pid``
holds the listening socket of the node's XML-RPC port (``/proc/<pid>/net/tcp*`` for the socket's inode, then
``/proc/<pid>/fd`` for that inode) before anything is read; a pid that cannot be verified is not measured.

CPU is the process's user + system time over the measurement window (``/proc/<pid>/stat``, clock ticks) in
cores (1.0 = one core busy); memory its resident set (``VmRSS``) at the window's end, in MiB. A process shared
by several nodes (nodelets in one manager) reports the same figures for each.
"""

from __future__ import annotations

import os
import socket
import time
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Sample", "is_local_address", "owns_port", "rss_mib", "sample"]

PROC = Path("/proc")


@dataclass(frozen=True)
class Sample:
    pid: int
    start_ticks: int  # the process's start time: a reused pid has another
    cpu_ticks: int
    at: float


def is_local_address(host: str) -> bool:
    """Whether ``host`` names this machine: loopback, or an address a socket can bind here."""
    try:
        infos = socket.getaddrinfo(host, None, type=socket.SOCK_DGRAM)
    except OSError:
        return False
    for family, _, _, _, addr in infos:
        try:
            with socket.socket(family, socket.SOCK_DGRAM) as s:
                s.bind((addr[0], 0))
            return True
        except OSError:
            continue
    return False


def _listening_inodes(pid: int, port: int) -> set[str]:
    inodes = set()
    for name in ("tcp", "tcp6"):
        try:
            lines = (PROC / str(pid) / "net" / name).read_text().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            cols = line.split()
            if len(cols) > 9 and cols[3] == "0A" and int(cols[1].rsplit(":", 1)[1], 16) == port:
                inodes.add(cols[9])
    return inodes


def owns_port(pid: int, port: int) -> bool:
    """Whether process ``pid`` (as this machine numbers it) holds a socket listening on TCP ``port``."""
    inodes = _listening_inodes(pid, port)
    if not inodes:
        return False
    try:
        fds = list((PROC / str(pid) / "fd").iterdir())
    except OSError:
        return False
    for fd in fds:
        try:
            target = os.readlink(fd)
        except OSError:
            continue
        if target.startswith("socket:[") and target[8:-1] in inodes:
            return True
    return False


def sample(pid: int) -> Sample | None:
    try:
        text = (PROC / str(pid) / "stat").read_text()
    except OSError:
        return None
    fields = text[text.rindex(")") + 2 :].split()  # after the command name, which may hold spaces
    # fields[0] is field 3 (state): utime is field 14, stime 15, starttime 22
    return Sample(pid, int(fields[19]), int(fields[11]) + int(fields[12]), time.monotonic())


def cpu_cores(before: Sample, after: Sample) -> float | None:
    """Cores used between two samples of one process; None if the pid now names another process."""
    if before.pid != after.pid or before.start_ticks != after.start_ticks or after.at <= before.at:
        return None
    return (after.cpu_ticks - before.cpu_ticks) / os.sysconf("SC_CLK_TCK") / (after.at - before.at)


def rss_mib(pid: int) -> float | None:
    try:
        for line in (PROC / str(pid) / "status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    except (OSError, ValueError, IndexError):
        return None
    return None
