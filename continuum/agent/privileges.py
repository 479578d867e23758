"""What the command and the agent keep of root: the command nothing, the agent what scheduling needs.

The command is the deadline task, but it must not be able to leave its reservation: with root or
``CAP_SYS_NICE`` it could make itself ``SCHED_FIFO`` 99 (measured before this module: it could), clear
``SCHED_RESET_ON_FORK`` or give a child a deadline of its own. So the forked child, before its exec, drops to an
unprivileged user (``nobody`` unless told), loses every capability (effective, permitted, inheritable, ambient
and, where the agent may, the bounding set), sets ``no_new_privs`` (no set-uid binary or file capability gives
any back across exec) and ``RLIMIT_RTPRIO`` 0 (no unprivileged real-time priority either). The kernel keeps the
deadline parameters the agent set on it from outside (``sched_setattr`` on its pid at the exec stop).

The agent itself keeps ``CAP_SYS_NICE`` (the command's deadline, its own tracer thread at SCHED_FIFO) and
``CAP_KILL`` (forwarding signals to a command that is now another user) and drops the rest once the command runs.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import pwd
import resource
from dataclasses import dataclass
from pathlib import Path

PR_SET_NO_NEW_PRIVS = 38
PR_CAPBSET_DROP = 24
PR_CAP_AMBIENT = 47
PR_CAP_AMBIENT_CLEAR_ALL = 4
CAP_KILL = 5
CAP_SYS_NICE = 23
#: What the agent keeps once the command runs (see the module docstring).
AGENT_CAPS = (CAP_KILL, CAP_SYS_NICE)
_CAP_VERSION_3 = 0x20080522
NOBODY = 65534

_libc = ctypes.CDLL(None, use_errno=True)


class _CapHeader(ctypes.Structure):
    _fields_ = [("version", ctypes.c_uint32), ("pid", ctypes.c_int)]


class _CapData(ctypes.Structure):
    _fields_ = [("effective", ctypes.c_uint32), ("permitted", ctypes.c_uint32), ("inheritable", ctypes.c_uint32)]


@dataclass(frozen=True)
class User:
    """Who the command runs as."""

    uid: int
    gid: int


def parse_user(text: str) -> User:
    """``NAME``, ``UID`` or ``UID:GID`` (a name's group is its primary one); ValueError names the problem."""
    name, _, group = text.partition(":")
    if name.isdigit():
        uid = int(name)
        try:
            gid = pwd.getpwuid(uid).pw_gid
        except KeyError:
            gid = uid
    else:
        try:
            entry = pwd.getpwnam(name)
        except KeyError:
            raise ValueError(f"no user {name!r}") from None
        uid, gid = entry.pw_uid, entry.pw_gid
    if group:
        if not group.isdigit():
            raise ValueError(f"group {group!r} must be a number")
        gid = int(group)
    if uid == 0 or gid == 0:
        raise ValueError("the command may not run as root (uid or gid 0): it could leave its reservation")
    if uid >= 2**32 - 1 or gid >= 2**32 - 1:
        raise ValueError(f"{text!r} is out of range")
    return User(uid, gid)


def default_user() -> User:
    """``nobody`` when the agent is root; otherwise the agent's own user (it cannot change it), capabilities gone."""
    if os.geteuid() == 0:
        return User(NOBODY, NOBODY)
    return User(os.getuid(), os.getgid())


def _last_cap() -> int:
    try:
        return int(Path("/proc/sys/kernel/cap_last_cap").read_text())
    except (OSError, ValueError):
        return 40


def _prctl(option: int, arg: int = 0, arg3: int = 0) -> int:
    result = _libc.prctl(ctypes.c_int(option), ctypes.c_ulong(arg), ctypes.c_ulong(arg3), ctypes.c_ulong(0),
                         ctypes.c_ulong(0))  # fmt: skip
    return 0 if result == 0 else ctypes.get_errno()


def _capset(caps: tuple[int, ...]) -> None:
    """This thread's effective and permitted sets become ``caps``, its inheritable set empty (only ever reduces)."""
    data = (_CapData * 2)()
    for cap in caps:
        data[cap // 32].effective |= 1 << (cap % 32)
        data[cap // 32].permitted |= 1 << (cap % 32)
    header = _CapHeader(_CAP_VERSION_3, 0)
    if _libc.capset(ctypes.byref(header), data) != 0:
        code = ctypes.get_errno()
        raise OSError(code, f"capset: {os.strerror(code)}")


def _drop_bounding(keep: tuple[int, ...]) -> None:
    # EPERM without CAP_SETPCAP (an agent that is not root): no_new_privs already keeps exec from raising anything.
    for cap in range(_last_cap() + 1):
        if cap not in keep:
            _prctl(PR_CAPBSET_DROP, cap)


def status_caps(pid: int | str = "self") -> dict[str, int]:
    """``CapEff``/``CapPrm``/``CapInh``/``CapBnd``/``CapAmb`` of a process, as integers."""
    out = {}
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        key, _, value = line.partition(":")
        if key.startswith("Cap"):
            out[key] = int(value.strip(), 16)
    return out


def drop_for_command(user: User) -> None:
    """In the forked child, before exec: no root, no capability, no way back. Raises OSError (nothing half-done
    is ever exec'd: the caller reports the errno and exits)."""
    if _prctl(PR_SET_NO_NEW_PRIVS, 1):
        raise OSError(ctypes.get_errno(), "prctl(PR_SET_NO_NEW_PRIVS) failed")
    _drop_bounding(())
    _prctl(PR_CAP_AMBIENT, PR_CAP_AMBIENT_CLEAR_ALL)
    resource.setrlimit(resource.RLIMIT_RTPRIO, (0, 0))
    if (os.getuid(), os.geteuid()) != (user.uid, user.uid) or os.getgid() != user.gid:
        os.setgroups([])
        os.setresgid(user.gid, user.gid, user.gid)
        os.setresuid(user.uid, user.uid, user.uid)  # leaving uid 0 clears the permitted and effective sets
    _capset(())
    caps = status_caps()
    if caps.get("CapEff") or caps.get("CapPrm") or caps.get("CapAmb") or os.geteuid() == 0:
        raise OSError(1, f"privileges remain after the drop: uid {os.geteuid()}, {caps}")


def drop_for_agent() -> list[str]:
    """In the agent's tracer thread before any other thread starts: keep :data:`AGENT_CAPS`, drop the rest (best
    effort: an agent without them keeps what it has). The names of the capabilities it now has."""
    _prctl(PR_SET_NO_NEW_PRIVS, 1)
    have = status_caps().get("CapEff", 0)
    keep = tuple(c for c in AGENT_CAPS if have >> c & 1)
    _drop_bounding(keep)
    with contextlib.suppress(OSError):  # an agent without them keeps what it has
        _capset(keep)
    names = {CAP_KILL: "CAP_KILL", CAP_SYS_NICE: "CAP_SYS_NICE"}
    now = status_caps().get("CapEff", 0)
    return [names.get(c, str(c)) for c in range(_last_cap() + 1) if now >> c & 1]
