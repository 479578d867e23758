"""Run a command as a SCHED_DEADLINE task and count the SIGXCPU its runtime overruns raise.

Why ptrace: with ``SCHED_FLAG_DL_OVERRUN`` the kernel sends SIGXCPU to the deadline task itself, i.e. to the
command, whose default action for SIGXCPU is to die, and an arbitrary command neither counts nor ignores it (an
ignored signal would stay ignored across exec, but then nothing counts it). The thesis injects a C hook into each
container for this. The agent instead traces the command (``PTRACE_SEIZE``): every signal bound for a traced
thread first stops it (*signal-delivery-stop*) and the tracer decides whether it is delivered. The agent counts
each SIGXCPU there and suppresses it, and passes every other signal on unchanged. This needs no change to the
command or its image, works for any executable (static, Go, Python...), and a deadline task may be traced
(only fork is forbidden to it, see below). Threads the command creates are traced too
(``PTRACE_O_TRACECLONE``) since SIGXCPU is process-directed and may be delivered to any of them; child processes
are not traced. Cost: one stop per overrun (a few microseconds), nothing otherwise.

Order of events: the agent forks; the child waits on a pipe until the agent has seized it and execs the command
(an exec failure goes back through a close-on-exec pipe). The exec stops the child (``PTRACE_O_TRACEEXEC``)
before the command's first instruction; there the agent makes it a deadline task (``sched_setattr`` on its
pid), so the budget is spent on the command only, not on the exec (tearing down the forked copy of the agent
costs a few ms of CPU, which would already overrun a short runtime). If the kernel refuses (EBUSY: admission),
the stopped child is killed: the command never runs. ``SCHED_FLAG_RESET_ON_FORK`` is set: a deadline task may
not fork, so without it the command could not start a thread or a child; with it those start as ordinary
SCHED_OTHER tasks and only the command's main thread is the deadline task.
"""

from __future__ import annotations

import ctypes
import errno
import os
import signal
import struct
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from .privileges import User, drop_for_command
from .sched import DeadlineParams, set_deadline

PTRACE_CONT = 7
PTRACE_SEIZE = 0x4206
PTRACE_LISTEN = 0x4208
PTRACE_O_TRACECLONE = 0x08
PTRACE_O_TRACEEXEC = 0x10
PTRACE_EVENT_EXEC = 4
PTRACE_O_EXITKILL = 0x100000
PTRACE_EVENT_STOP = 128
__WALL = 0x40000000
_STOP_SIGNALS = {signal.SIGSTOP, signal.SIGTSTP, signal.SIGTTIN, signal.SIGTTOU}

_libc = ctypes.CDLL(None, use_errno=True)
_libc.ptrace.argtypes = [ctypes.c_long, ctypes.c_long, ctypes.c_void_p, ctypes.c_void_p]
_libc.ptrace.restype = ctypes.c_long


def _ptrace(request: int, pid: int, data: int = 0) -> None:
    if _libc.ptrace(request, pid, None, ctypes.c_void_p(data)) == -1:
        code = ctypes.get_errno()
        if code != errno.ESRCH:  # the thread died meanwhile: nothing to resume
            raise OSError(code, f"ptrace: {os.strerror(code)}")


@dataclass
class Outcome:
    """How the command ended. ``refused``: sched_setattr's errno (the command was killed before its first
    instruction); ``exec_errno``: exec failed; else ``exit_code`` (or ``signal`` if a signal killed it)."""

    pid: int
    refused: int | None = None
    exec_errno: int | None = None
    drop_errno: int | None = None
    exit_code: int | None = None
    signal: int | None = None


def _child(go: int, report: int, argv: Sequence[str], user: User | None, env: dict[str, str] | None) -> None:
    """In the forked child: wait to be traced, drop privileges, exec. Never returns."""
    try:
        os.read(go, 1)
        os.close(go)
        # Python ignores SIGPIPE and SIGXFSZ; an ignored signal stays ignored across exec.
        for sig in (signal.SIGPIPE, signal.SIGXFSZ, signal.SIGINT, signal.SIGTERM, signal.SIGXCPU):
            signal.signal(sig, signal.SIG_DFL)
        if user is not None:
            try:
                drop_for_command(user)
            except OSError as exc:
                os.write(report, struct.pack("=ci", b"p", exc.errno or 1))
                os._exit(126)
        try:
            if env is None:
                os.execvp(argv[0], list(argv))
            else:
                os.execvpe(argv[0], list(argv), env)
        except OSError as exc:
            os.write(report, struct.pack("=ci", b"e", exc.errno or 0))
    finally:
        os._exit(127)


def run_traced(
    argv: Sequence[str],
    params: DeadlineParams | None,
    on_overrun: Callable[[float], None],
    on_started: Callable[[int], None] | None = None,
    user: User | None = None,
    env: dict[str, str] | None = None,
) -> Outcome:
    """Run ``argv`` (as a deadline task with ``params``; None: unchanged policy) until it exits, as ``user`` with
    no capability (None: as the agent, privileges unchanged), with ``env`` (None: the agent's environment).

    ``on_overrun(time.time())`` is called for each SIGXCPU, from this thread (the tracer: ptrace requests must
    come from the thread that seized the child). ``on_started(pid)`` once the command runs.
    """
    go_r, go_w = os.pipe()
    rep_r, rep_w = os.pipe2(os.O_CLOEXEC)
    pid = os.fork()
    if pid == 0:
        os.close(go_w)
        os.close(rep_r)
        _child(go_r, rep_w, argv, user, env)
    os.close(go_r)
    os.close(rep_w)
    try:
        _ptrace(PTRACE_SEIZE, pid, PTRACE_O_TRACECLONE | PTRACE_O_TRACEEXEC | PTRACE_O_EXITKILL)
    except OSError:
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        os.close(go_w)
        os.close(rep_r)
        raise
    os.write(go_w, b"x")
    os.close(go_w)
    # EOF: exec succeeded (the close-on-exec pipe closed); otherwise what failed, and its errno.
    failure = b""
    while len(failure) < 5:
        chunk = os.read(rep_r, 5 - len(failure))
        if not chunk:
            break
        failure += chunk
    os.close(rep_r)
    outcome = Outcome(pid)
    if len(failure) == 5:
        kind, code = struct.unpack("=ci", failure)
        if kind == b"p":
            outcome.drop_errno = code
        else:
            outcome.exec_errno = code

    def exec_stop() -> None:
        """The command is loaded and stopped before its first instruction: make it the deadline task."""
        if params is not None:
            try:
                set_deadline(params, pid)
            except OSError as exc:
                outcome.refused = exc.errno or 0
                os.kill(pid, signal.SIGKILL)  # it never runs without its guarantee
                return
        if on_started is not None:
            on_started(pid)

    _trace_loop(pid, outcome, on_overrun, exec_stop)
    return outcome


def _trace_loop(pid: int, outcome: Outcome, on_overrun: Callable[[float], None], exec_stop: Callable[[], None]
                ) -> None:  # fmt: skip
    """Wait for the command (and reap anything else, as PID 1 of a container must) until its main thread ends."""
    execed = False
    while True:
        try:
            tid, status = os.waitpid(-1, __WALL)
        except ChildProcessError:
            return
        if os.WIFEXITED(status) or os.WIFSIGNALED(status):
            if tid == pid:
                if os.WIFEXITED(status):
                    outcome.exit_code = os.WEXITSTATUS(status)
                else:
                    outcome.signal = os.WTERMSIG(status)
                return
            continue  # one of its threads, or an orphan we reaped
        if not os.WIFSTOPPED(status):
            continue
        sig, event = os.WSTOPSIG(status), status >> 16
        if event == 0:  # signal-delivery-stop
            if sig == signal.SIGXCPU:
                on_overrun(time.time())
                _ptrace(PTRACE_CONT, tid, 0)  # suppressed: counted, not delivered
            else:
                _ptrace(PTRACE_CONT, tid, sig)
        elif event == PTRACE_EVENT_EXEC and tid == pid and not execed:
            execed = True
            exec_stop()
            if outcome.refused is None:
                _ptrace(PTRACE_CONT, tid, 0)
        elif event == PTRACE_EVENT_STOP and sig in _STOP_SIGNALS:
            _ptrace(PTRACE_LISTEN, tid)  # a group-stop (Ctrl-Z, SIGSTOP): stay stopped until SIGCONT
        else:
            _ptrace(PTRACE_CONT, tid, 0)  # clone events, the new thread's initial stop
