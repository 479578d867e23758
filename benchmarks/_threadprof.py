"""Where a process's CPU goes, by thread and by function, without a profiler of every call (benchmarks only).

cProfile follows one thread and slows it several times; a scheduler's time is spread over its loop, watch,
Binding, Event and writer threads. :class:`ThreadProfile` samples, every ``interval`` seconds, the state of each
thread of this process in ``/proc/self/task/<tid>/stat`` (Linux): a thread found running (``R``) counts its
Python stack (``sys._current_frames``) as one CPU sample, a thread asleep (waiting for the network, a lock or
the GIL) counts nothing. At the end it also reads each thread's CPU seconds (utime + stime), so per thread
group (a pool's threads together) the CPU is exact and the functions are a sample.
"""

from __future__ import annotations

import os
import re
import sys
import threading
import time
from collections import Counter

TICK = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100
_SUFFIX = re.compile(r"[_-]\d+$|\s*\(.*\)$")


def group_of(name: str) -> str:
    """A pool's threads together: ``rt-bind_3`` -> ``rt-bind``, ``Thread-7 (worker)`` -> ``Thread``."""
    name = _SUFFIX.sub("", name)
    return re.sub(r"-\d+$", "", name)


def _stat(tid: int) -> tuple[str, float] | None:
    """(state letter, CPU seconds) of a thread of this process; None when it ended."""
    try:
        with open(f"/proc/self/task/{tid}/stat", "rb") as f:
            text = f.read().decode()
    except OSError:
        return None
    rest = text[text.rindex(")") + 2 :].split()
    return rest[0], (int(rest[11]) + int(rest[12])) / TICK


def _plumbing(where: str) -> bool:
    """Frames every thread of a kind shares (thread start, pool worker loop): no information."""
    return where.startswith(("threading.py:", "thread.py:_worker", "thread.py:run"))


class ThreadProfile:
    def __init__(self, interval: float = 0.005, depth: int = 40) -> None:
        self.interval = interval
        self.depth = depth
        self.samples = 0
        self.own: Counter[tuple[str, str]] = Counter()  # (group, function) -> samples as the running leaf
        self.inclusive: Counter[tuple[str, str]] = Counter()  # (group, function) -> samples on the stack
        self.running: Counter[str] = Counter()  # group -> samples
        self.cpu: dict[int, tuple[str, float]] = {}  # tid -> (group, latest CPU seconds)
        self.stop = threading.Event()
        self.own_cpu = 0.0
        self.thread = threading.Thread(target=self._loop, daemon=True, name="threadprof")

    def start(self) -> None:
        self.began = {t: s[1] for t in self._tids() if (s := _stat(t))}
        self.thread.start()

    @staticmethod
    def _tids() -> list[int]:
        return [int(t) for t in os.listdir("/proc/self/task")]

    def _loop(self) -> None:
        me = threading.get_native_id()
        began = time.thread_time()
        while not self.stop.wait(self.interval):
            self.own_cpu = time.thread_time() - began
            names = {t.native_id: group_of(t.name) for t in threading.enumerate()}
            idents = {t.native_id: t.ident for t in threading.enumerate()}
            frames = sys._current_frames()
            self.samples += 1
            for tid in self._tids():
                if tid == me:
                    continue
                stat = _stat(tid)
                if stat is None:
                    continue
                group = names.get(tid, "?")
                self.cpu[tid] = (group, stat[1])
                if stat[0] != "R":
                    continue
                self.running[group] += 1
                frame = frames.get(idents.get(tid))  # type: ignore[arg-type]
                seen = set()
                leaf = True
                depth = 0
                while frame is not None and depth < self.depth:
                    code = frame.f_code
                    where = f"{os.path.basename(code.co_filename)}:{code.co_name}"
                    if leaf:
                        self.own[(group, where)] += 1
                        leaf = False
                    if where not in seen:
                        self.inclusive[(group, where)] += 1
                        seen.add(where)
                    frame = frame.f_back
                    depth += 1

    def _inclusive(self, per_group: int) -> list[list]:
        """The ``per_group`` functions most often on a running stack of each thread group."""
        out: list[list] = []
        kept: Counter[str] = Counter()
        for (group, where), n in self.inclusive.most_common():
            if not _plumbing(where) and kept[group] < per_group:
                kept[group] += 1
                out.append([group, where, n])
        return out

    def finish(self) -> dict:
        self.stop.set()
        self.thread.join(timeout=5)
        for tid in self._tids():
            stat = _stat(tid)
            if stat is not None and tid in self.cpu:
                self.cpu[tid] = (self.cpu[tid][0], stat[1])
        by_group: Counter[str] = Counter()
        for tid, (group, seconds) in self.cpu.items():
            by_group[group] += seconds - self.began.get(tid, 0.0)
        return {
            "cpu_by_thread": {g: round(s, 3) for g, s in by_group.most_common()},
            "samples": self.samples,
            "running": dict(self.running.most_common()),
            "own": [[g, f, n] for (g, f), n in self.own.most_common(30)],
            "inclusive": self._inclusive(14),
            "self_cpu": round(self.own_cpu, 3),
        }
