"""The coordinator (thesis §3.5, Fig. 3.42; spec 03 §9): elected among the handlers, it runs the
allocation MILP every period on the handlers' statistics and sends EXEC/MIGRATE requests for the
differences from the current allocation.

Exactly one handler has each monitor active (spec 03 §9), so the coordinator never starts a second copy:

* a handler whose report is late (not *live*: a busy or descheduled process) is left alone with its
  monitors; only one silent for ``dead_after`` seconds (or shut down) is *gone*, and only then are its
  monitors started afresh elsewhere;
* migrations in flight are kept in Redis (:meth:`Bus.moving`), not in this object, so a coordinator
  elected while a hand-over is under way does not move or restart that monitor.
"""

from __future__ import annotations

import time
from collections.abc import Collection, Mapping
from typing import TYPE_CHECKING

from continuum.engine.verification.monitor_milp import MonitorAllocator
from continuum.engine.verification.stl_monitor import synthesize

if TYPE_CHECKING:
    from .bus import Bus
    from .handler import Handler


def gone_handlers(reports: Mapping[str, Mapping], dead_after: float) -> set[str]:
    """Handlers silent for ``dead_after`` seconds, or shutting down: their monitors may start elsewhere."""
    now = time.time()
    return {n for n, r in reports.items() if now - float(r.get("wall", 0)) > dead_after or r.get("shutting_down")}


def hand_over(bus: Bus, allocation: Mapping[str, str], live: Collection[str], gone: Collection[str]) -> list[str]:
    """Send the requests that carry out ``allocation`` (monitor -> handler) and record it; returns the monitors
    acted on. The one rule for every caller (the elected coordinator, the server applying a stored run):

    * a monitor never placed, or whose handler is gone, is started afresh (EXEC) on its target;
    * one on a live handler migrates (MIGRATE, Fig. 3.43), recorded in ``{p}:moving`` first;
    * one on a handler that is late but not gone is left alone: it still runs the monitor, and a second copy
      would duplicate its verdicts;
    * one whose migration is in flight is left alone, unless the source or target of that migration is gone
      (it will never finish: the record is dropped and the monitor placed as above);
    * a target that is not live gets nothing (the request would wait in its stream).
    """
    in_flight = set()
    for monitor, move in bus.moving().items():
        if move["source"] in gone or move["target"] in gone:
            bus.stop_moving(monitor)
        else:
            in_flight.add(monitor)
    current = bus.allocation()
    acted = []
    for monitor, node in allocation.items():
        host = current.get(monitor)
        if monitor in in_flight or host == node or node not in live:
            continue
        if host is None or host in gone:
            bus.send(node, "EXEC", monitors=[monitor])
        elif host in live:
            bus.start_moving(monitor, host, node)  # before MIGRATE: the target may answer at once
            bus.send(host, "MIGRATE", monitor=monitor, to=node)
        else:
            continue
        bus.set_allocation(monitor, node)
        acted.append(monitor)
    return acted


class Coordinator:
    def __init__(self, handler: Handler, period: float = 1.0, default_cpu: float = 0.5, dead_after: float = 10.0):
        self.handler, self.bus, self.period = handler, handler.bus, period
        self.dead_after = dead_after
        self.allocator = MonitorAllocator(window=10, time_limit=max(0.1, period / 2))
        self.default_cpu = default_cpu
        self.next_run = 0.0
        self.variables: dict[str, list[str]] = {}
        self.last: dict | None = None
        self.degraded: set[str] = set()

    def maybe_allocate(self) -> None:
        now = time.monotonic()
        if now < self.next_run:
            return
        self.next_run = now + self.period
        reports = self.bus.handlers()
        live = self.live_handlers(reports)
        gone = gone_handlers(reports, self.dead_after)
        doc = self.stats_doc(live)
        if doc is None:
            return
        result = self.allocator.step(doc)
        self.last = result.to_dict()
        hand_over(self.bus, result.allocation, live, gone)
        # overload strategy 2 on the overloaded units' tolerant monitors (strategy 1, priority by active
        # instances, is always on in the handlers' schedulers)
        drop = set(result.drop_events)
        for monitor in sorted(drop - self.degraded):
            self.bus.send(result.allocation[monitor], "DEGRADE", monitors=[monitor], drop=True)
        for monitor in sorted(self.degraded - drop):
            self.bus.send(result.allocation[monitor], "DEGRADE", monitors=[monitor], drop=False)
        self.degraded = drop

    def live_handlers(self, reports: dict[str, dict] | None = None) -> dict[str, dict]:
        """Handlers that reported within 3 stats periods: the MILP places monitors on these only."""
        horizon = 3 * self.handler.stats_period
        reports = self.bus.handlers() if reports is None else reports
        return {
            name: report
            for name, report in reports.items()
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
