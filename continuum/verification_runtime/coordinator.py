"""The coordinator (thesis §3.5, Fig. 3.42; spec 03 §9): elected among the handlers, it runs the
allocation MILP every period on the handlers' statistics and sends EXEC/MIGRATE requests for the
differences from the current allocation."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

from continuum.engine.verification.monitor_milp import MonitorAllocator
from continuum.engine.verification.stl_monitor import synthesize

if TYPE_CHECKING:
    from .handler import Handler


class Coordinator:
    def __init__(self, handler: Handler, period: float = 1.0, default_cpu: float = 0.5):
        self.handler, self.bus, self.period = handler, handler.bus, period
        self.allocator = MonitorAllocator(window=10, time_limit=max(0.1, period / 2))
        self.default_cpu = default_cpu
        self.next_run = 0.0
        self.acks_read = 0
        self.moving: dict[str, str] = {}
        self.variables: dict[str, list[str]] = {}
        self.last: dict | None = None
        self.degraded: set[str] = set()

    def maybe_allocate(self) -> None:
        now = time.monotonic()
        if now < self.next_run:
            return
        self.next_run = now + self.period
        self._read_acks()
        live = self.live_handlers()
        doc = self.stats_doc(live)
        if doc is None:
            return
        result = self.allocator.step(doc)
        self.last = result.to_dict()
        current = self.bus.allocation()
        for monitor, node in result.allocation.items():
            host = current.get(monitor)
            if monitor in self.moving or host == node:
                continue
            if host is None or host not in live:  # never placed, or its handler is gone: start it afresh
                self.bus.send(node, "EXEC", monitors=[monitor])
            else:
                self.bus.send(host, "MIGRATE", monitor=monitor, to=node)
                self.moving[monitor] = node
            self.bus.set_allocation(monitor, node)
        # overload strategy 2 on the overloaded units' tolerant monitors (strategy 1, priority by active
        # instances, is always on in the handlers' schedulers)
        drop = set(result.drop_events)
        for monitor in sorted(drop - self.degraded):
            self.bus.send(result.allocation[monitor], "DEGRADE", monitors=[monitor], drop=True)
        for monitor in sorted(self.degraded - drop):
            self.bus.send(result.allocation[monitor], "DEGRADE", monitors=[monitor], drop=False)
        self.degraded = drop

    def _read_acks(self) -> None:
        acks = self.bus.acks()
        for kind, body in acks[self.acks_read :]:
            if kind in ("migrated", "migrate_refused"):
                self.moving.pop(body["monitor"], None)
        self.acks_read = len(acks)

    def live_handlers(self) -> dict[str, dict]:
        horizon = 3 * self.handler.stats_period
        return {
            name: report
            for name, report in self.bus.handlers().items()
            if time.time() - report["wall"] <= horizon and not report.get("shutting_down")
        }

    def stats_doc(self, live: dict[str, dict]) -> dict | None:
        """The ``continuum.monitorstats/v1`` document built from the live handlers' reports."""
        monitors = self.bus.monitors()
        if not live or not monitors:
            return None
        nodes = [
            {
                "name": name,
                "available_cpu": min(100.0, r["free_cpu"] + r.get("verification_cpu", 0.0)),
                "threshold": r.get("threshold", 100.0),
            }
            for name, r in sorted(live.items())
        ]
        for name, spec in monitors.items():
            if name not in self.variables:
                self.variables[name] = sorted(synthesize(spec["assertion"], spec.get("constants")).variables)
        topics = sorted({v for vs in self.variables.values() for v in vs})
        topic_docs = [
            {
                "name": t,
                "delay": {n: float(r.get("delay_ms", 0.0)) for n, r in live.items()},
                "cpu": {n: 0.2 if r.get("delay_ms", 0.0) > 0 else 0.0 for n, r in live.items()},
            }
            for t in topics
        ]
        allocation = self.bus.allocation()
        monitor_docs = []
        for name in sorted(monitors):
            cpu = {n: r["monitor_cpu"][name] for n, r in live.items() if name in r.get("monitor_cpu", {})}
            if not cpu:
                cpu = {n: self.default_cpu for n in live}
            current = allocation.get(name)
            monitor_docs.append(
                {
                    "name": name,
                    "topics": self.variables[name],
                    "cpu": cpu,
                    "current": current if current in live else None,
                }
            )
        return {"format": "continuum.monitorstats/v1", "nodes": nodes, "topics": topic_docs, "monitors": monitor_docs}
