"""A monitor handler process (thesis §3.5, Fig. 3.42; spec 03 §9, §11).

One handler runs per computing unit. It can run every monitor of the registry (it synthesises them from
their assertions), receives the SUV's events from the Redis event stream, evaluates its active monitors
with a priority scheduler (priority = active instances, plus aging so nothing starves, within a time
slice), reports statistics, takes part in the coordinator election and carries out the coordinator's
requests: EXEC (run these monitors), MIGRATE (move one to another handler, Fig. 3.43) and SHUTDOWN.

Migration over Redis follows :mod:`continuum.engine.verification.stl_monitor`'s protocol functions:

    coordinator --MIGRATE(m, H2)--> H1: migrate_begin (off the scheduler, still buffering)
    H1 --MIGRATION_START(m)--> H2: standby copy, subscribed from here on
    H2 --T0(m, t0, t0_id)--> H1: once H2 could sort; t0_id = stream id of H2's first event at t0
    H1 waits until it has read the event stream up to t0_id (so it holds every event before T0), then
    H1 --HANDOVER(m, payload)--> H2: migrate_handover (state + compressed events with ts < T0)
    H2: migrate_complete, schedules m, acknowledges.

Run: ``python -m continuum.verification_runtime.handler --name edge --prefix cv [--free-cpu 40]``.
"""

from __future__ import annotations

import argparse
import os
import signal
import time
from dataclasses import dataclass, field

from continuum.engine.verification.stl_monitor import (
    Monitor,
    Program,
    migrate_begin,
    migrate_complete,
    migrate_handover,
    migrate_t0,
    standby_copy,
    synthesize,
)

from .bus import Bus
from .coordinator import Coordinator


def _id(entry_id: str) -> tuple[int, int]:
    ms, _, seq = entry_id.partition("-")
    return int(ms), int(seq or 0)


@dataclass
class Copy:
    """This handler's copy of one monitor and its role in a migration."""

    monitor: Monitor
    role: str  # "active", "source" (migrating away) or "standby" (migrating here)
    peer: str | None = None
    seen: list[tuple[str, float]] = field(default_factory=list)  # standby: (stream id, ts) of events received
    start_after: str = "0-0"  # standby: only events after the source's read position at step 2a
    t0_sent: bool = False
    handover: tuple[float, str, str] | None = None  # source: (t0, t0_id, destination) waiting for the stream
    cpu_seconds: float = 0.0
    last_run: float = field(default_factory=time.monotonic)


class Handler:
    def __init__(
        self,
        name: str,
        bus: Bus,
        *,
        free_cpu: float | None = None,
        cores: int | None = None,
        delay_ms: float = 0.0,
        threshold: float = 100.0,
        stats_period: float = 0.2,
        allocate_period: float = 1.0,
        allocate: bool = False,
        time_slice: int = 200,
        aging: float = 10.0,
        monitor_cpu: float | None = None,
        discovery: float = 1.0,
        max_lag_ms: float = 500.0,
        max_buffer: int = 10_000,
        dead_after: float = 10.0,
    ):
        self.name, self.bus = name, bus
        self.free_cpu, self.cores = free_cpu, cores or os.cpu_count() or 1
        self.delay_ms, self.threshold = delay_ms, threshold
        self.stats_period, self.time_slice, self.aging = stats_period, time_slice, aging
        self.fixed_monitor_cpu = monitor_cpu  # simulations and tests: report this instead of measuring
        self.programs: dict[str, tuple[Program, dict]] = {}
        self.copies: dict[str, Copy] = {}
        self.events_id = bus.last_event_id()  # a new handler listens from now on
        self.req_id = "0-0"
        self.ended = False
        self.shutting_down = False
        self.next_stats = 0.0
        self.period_start = time.monotonic()
        self.coordinator = Coordinator(self, period=allocate_period, dead_after=dead_after) if allocate else None
        self.is_coordinator = False
        self.discovery_until = time.monotonic() + discovery  # hear the other handlers before electing
        self.degraded: set[str] = set()  # monitors allowed to drop events while this unit is overloaded
        self.max_lag_ms, self.max_buffer = max_lag_ms, max_buffer

    # ---- registry ------------------------------------------------------------------------------
    def program(self, monitor: str) -> tuple[Program, dict]:
        if monitor not in self.programs:
            spec = self.bus.monitors()[monitor]
            options = dict(spec.get("options", {}))
            self.programs[monitor] = (synthesize(spec["assertion"], spec.get("constants")), options)
        return self.programs[monitor]

    # ---- main loop -----------------------------------------------------------------------------
    def run(self) -> None:
        while not self.finished():
            self.step()
        self.report()

    def finished(self) -> bool:
        busy = any(c.role != "active" for c in self.copies.values())
        return self.shutting_down and self.ended and not busy and self._flushed

    _flushed = False

    def step(self) -> None:
        self.handle_requests()
        self.read_events(block_ms=None if self.any_backlog() else 20)
        self.protocol()
        self.evaluate()
        now = time.monotonic()
        if now >= self.next_stats:
            self.report()
            self.elect()
            self.next_stats = now + self.stats_period
        if self.coordinator is not None and self.is_coordinator:
            self.coordinator.maybe_allocate()
        if self.shutting_down and self.ended and not any(c.role != "active" for c in self.copies.values()):
            self.flush_all()

    def any_backlog(self) -> bool:
        return any(c.role == "active" and c.monitor.backlog for c in self.copies.values())

    # ---- requests --------------------------------------------------------------------------------
    def handle_requests(self) -> None:
        for entry_id, kind, body in self.bus.requests(self.name, self.req_id):
            self.req_id = entry_id
            action = getattr(self, f"on_{kind.lower()}", None)
            if action is None:
                self.bus.ack("unknown_request", handler=self.name, type=kind)
            else:
                action(**body)

    def on_exec(self, monitors: list[str]) -> None:
        for m in monitors:
            if m not in self.copies:
                program, options = self.program(m)
                self.copies[m] = Copy(Monitor(program, **options), "active")
            self.bus.ack("exec", monitor=m, handler=self.name)

    def on_migrate(self, monitor: str, to: str) -> None:
        copy = self.copies.get(monitor)
        if copy is None or copy.role != "active" or to == self.name:
            if copy is None or copy.role == "active":  # not a hand-over of ours in flight: nothing will finish it
                self.bus.stop_moving(monitor)
            self.bus.ack("migrate_refused", monitor=monitor, handler=self.name, to=to)
            return
        migrate_begin(copy.monitor)  # step 2a
        copy.role, copy.peer = "source", to
        # step 2b; H2 must not take events H1 may already have evaluated: it starts after H1's position
        self.bus.send(to, "MIGRATION_START", monitor=monitor, source=self.name, after=self.events_id)

    def on_migration_start(self, monitor: str, source: str, after: str) -> None:
        program, options = self.program(monitor)
        copy = Copy(standby_copy(program, **options), "standby", peer=source, start_after=after)  # step 3
        self.copies[monitor] = copy

    def on_t0(self, monitor: str, t0: float, t0_id: str) -> None:
        self.copies[monitor].handover = (t0, t0_id, self.copies[monitor].peer)

    def on_handover(self, monitor: str, payload: dict, source: str) -> None:
        copy = self.copies[monitor]
        migrate_complete(copy.monitor, payload)  # step 6
        copy.role, copy.peer, copy.seen = "active", None, []
        moved = len(payload["state"]["pre"].get("bits", []))  # instants handed over, compressed (step 5)
        self.bus.stop_moving(monitor)  # installed: a coordinator may move it again
        self.bus.ack("migrated", monitor=monitor, source=source, handler=self.name, moved=moved)

    def on_degrade(self, monitors: list[str], drop: bool = True) -> None:
        """Overload strategy 2 on (or off) for these monitors (only tolerant ones ever drop)."""
        if drop:
            self.degraded.update(monitors)
        else:
            self.degraded.difference_update(monitors)

    def on_shutdown(self) -> None:
        self.shutting_down = True

    # ---- events ----------------------------------------------------------------------------------
    def read_events(self, block_ms: int | None) -> None:
        if self.ended:
            return
        for entry_id, event in self.bus.read_events(self.events_id, block_ms=block_ms):
            self.events_id = entry_id
            if event is None:
                self.ended = True
                break
            var, _, ts = event
            for copy in self.copies.values():
                if var not in copy.monitor.program.deps:  # a monitor only subscribes to its own signals
                    continue
                if copy.role == "standby":
                    if _id(entry_id) <= _id(copy.start_after):
                        continue
                    copy.seen.append((entry_id, ts))
                copy.monitor.push(*event)

    # ---- migration protocol ------------------------------------------------------------------------
    def protocol(self) -> None:
        for name, copy in list(self.copies.items()):
            if copy.role == "standby" and not copy.t0_sent:
                t0 = migrate_t0(copy.monitor, force=self.ended)  # step 4
                if t0 is not None:
                    t0_id = next((i for i, ts in copy.seen if ts >= t0), self.events_id)
                    self.bus.send(copy.peer, "T0", monitor=name, t0=t0, t0_id=t0_id)
                    copy.t0_sent = True
            elif copy.role == "source" and copy.handover is not None:
                t0, t0_id, destination = copy.handover
                if self.ended or _id(self.events_id) >= _id(t0_id):  # every event before T0 has been read
                    payload = migrate_handover(copy.monitor, t0)  # step 5
                    self.bus.send(destination, "HANDOVER", monitor=name, payload=payload, source=self.name)
                    del self.copies[name]

    # ---- evaluation (the handler's scheduler) --------------------------------------------------------
    def evaluate(self) -> None:
        now = time.monotonic()
        runnable = [(n, c) for n, c in self.copies.items() if c.role == "active" and c.monitor.backlog]
        # priority: active instances (overload strategy 1) plus aging for the time spent waiting
        runnable.sort(key=lambda nc: -(nc[1].monitor.active_instances + self.aging * (now - nc[1].last_run)))
        for name, copy in runnable:
            m = copy.monitor
            if name in self.degraded and m.tolerant and m.lagging(self.max_lag_ms, self.max_buffer):
                m.drop_and_reset()  # strategy 2: throw the backlog away, reset the instances
                continue
            started = time.perf_counter()
            for v in copy.monitor.evaluate(max_instants=self.time_slice):
                self.bus.verdict(name, self.name, "violation", v.to_dict())
            copy.cpu_seconds += time.perf_counter() - started
            copy.last_run = time.monotonic()

    def flush_all(self) -> None:
        if self._flushed:
            return
        for name, copy in sorted(self.copies.items()):
            for v in copy.monitor.flush():
                self.bus.verdict(name, self.name, "violation", v.to_dict())
            m = copy.monitor
            final = {"verdict": m.verdict(), "counters": m.counters, "pending": m.pending_starts()}
            self.bus.verdict(name, self.name, "final", final)
        self._flushed = True

    # ---- statistics and election ---------------------------------------------------------------------
    def report(self) -> None:
        now = time.monotonic()
        span = max(now - self.period_start, 1e-6)
        monitor_cpu = {}
        for name, copy in self.copies.items():
            if copy.role == "active":
                measured = 100.0 * copy.cpu_seconds / span / self.cores
                monitor_cpu[name] = self.fixed_monitor_cpu if self.fixed_monitor_cpu is not None else measured
                copy.cpu_seconds = 0.0
        self.period_start = now
        free = self.free_cpu if self.free_cpu is not None else _measured_free_cpu(self.cores)
        self.bus.report(
            self.name,
            {
                "free_cpu": free,
                "verification_cpu": sum(monitor_cpu.values()),
                "cores": self.cores,
                "delay_ms": self.delay_ms,
                "threshold": self.threshold,
                "monitor_cpu": monitor_cpu,
                "active": sorted(n for n, c in self.copies.items() if c.role == "active"),
                "wall": time.time(),
                "shutting_down": self.shutting_down,
            },
        )

    def elect(self) -> None:
        """The handler with the most free CPU coordinates; a silent coordinator's lease expires (3 periods).

        A handler listens for ``discovery`` seconds after it starts before it stands; handlers that join
        later do not displace a coordinator that still answers (thesis §3.5).
        """
        ttl = int(3 * self.stats_period * 1000)
        current = self.bus.coordinator()
        if current == self.name:
            self.is_coordinator = self.bus.renew_coordinator(self.name, ttl)
            return
        self.is_coordinator = False
        if current is None and not self.shutting_down and time.monotonic() >= self.discovery_until:
            live = {
                name: report
                for name, report in self.bus.handlers().items()
                if time.time() - report["wall"] <= 3 * self.stats_period and not report.get("shutting_down")
            }
            best = max(live, key=lambda n: (live[n]["free_cpu"], n), default=None)
            if best == self.name:
                self.is_coordinator = self.bus.claim_coordinator(self.name, ttl)


def _measured_free_cpu(cores: int) -> float:
    try:
        load = os.getloadavg()[0]
    except OSError:
        return 100.0
    return max(0.0, 100.0 * (1.0 - load / cores))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description="Continuum monitor handler")
    parser.add_argument("--name", required=True)
    parser.add_argument("--prefix", default="cv")
    parser.add_argument("--redis", default=os.environ.get("CONTINUUM_REDIS_URL", "redis://127.0.0.1:6379/0"))
    parser.add_argument("--free-cpu", type=float, default=None, help="report this free CPU %% (default: measured)")
    parser.add_argument("--cores", type=int, default=None)
    parser.add_argument("--delay-ms", type=float, default=0.0, help="topic delay to this unit")
    parser.add_argument("--threshold", type=float, default=100.0)
    parser.add_argument("--stats-period", type=float, default=0.2)
    parser.add_argument("--allocate-period", type=float, default=1.0)
    parser.add_argument("--allocate", action="store_true", help="run the MILP when elected coordinator")
    parser.add_argument("--time-slice", type=int, default=200)
    parser.add_argument("--monitor-cpu", type=float, default=None, help="report this CPU %% per monitor")
    parser.add_argument("--discovery", type=float, default=1.0, help="seconds of listening before an election")
    parser.add_argument("--max-lag-ms", type=float, default=500.0, help="drop trigger: event-time lag")
    parser.add_argument("--max-buffer", type=int, default=10_000, help="drop trigger: events waiting")
    parser.add_argument(
        "--dead-after",
        type=float,
        default=10.0,
        help="seconds without a report before the coordinator restarts a handler's monitors elsewhere",
    )
    args = parser.parse_args(argv)
    handler = Handler(
        args.name,
        Bus(args.redis, args.prefix),
        free_cpu=args.free_cpu,
        cores=args.cores,
        delay_ms=args.delay_ms,
        threshold=args.threshold,
        stats_period=args.stats_period,
        allocate_period=args.allocate_period,
        allocate=args.allocate,
        time_slice=args.time_slice,
        monitor_cpu=args.monitor_cpu,
        discovery=args.discovery,
        max_lag_ms=args.max_lag_ms,
        max_buffer=args.max_buffer,
        dead_after=args.dead_after,
    )
    signal.signal(signal.SIGTERM, lambda *_: handler.on_shutdown())
    handler.run()


if __name__ == "__main__":
    main()


__all__ = ["Copy", "Handler", "main"]
