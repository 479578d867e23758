"""The node agent's ``/metrics`` (``--metrics-port``): what its Reporter counted, read at each scrape.

- ``continuum_agent_overruns_total``: runtime overruns (SIGXCPU) of the command;
- ``continuum_agent_kernel_rejections_total``: the kernel refused the deadline reservation (admission control);
- ``continuum_agent_reports_sent_total``: reports Continuum acknowledged; ``..._report_failures_total``: failed
  attempts; ``continuum_agent_reports_pending``: overruns counted and not delivered yet.

Each carries ``node`` and ``container``. The server starts after the command was forked (no thread is shared
with the child) and may linger after it ended (``--metrics-linger``) so that the last scrape sees the totals.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from prometheus_client import CollectorRegistry, start_http_server
from prometheus_client.core import CounterMetricFamily, GaugeMetricFamily
from prometheus_client.registry import Collector

from .report import Reporter

PREFIX = "continuum_agent"


class AgentCollector(Collector):
    def __init__(self, reporter: Reporter, node: str, container: str) -> None:
        self.reporter = reporter
        self.labels = [node, container]
        self.rejected = False

    def collect(self) -> Iterator[CounterMetricFamily | GaugeMetricFamily]:
        r = self.reporter
        for name, doc, value in (
            (f"{PREFIX}_overruns", "Runtime overruns (SIGXCPU) of the command", r.overruns),
            (f"{PREFIX}_kernel_rejections", "Deadline reservations the kernel refused", int(self.rejected)),
            (f"{PREFIX}_reports_sent", "Reports Continuum acknowledged", r.reports_acknowledged),
            (f"{PREFIX}_report_failures", "Report deliveries that failed", r.failures),
        ):
            family = CounterMetricFamily(name, doc, labels=["node", "container"])
            family.add_metric(self.labels, value)
            yield family
        pending = GaugeMetricFamily(
            f"{PREFIX}_reports_pending", "Overruns not delivered yet", labels=["node", "container"]
        )
        pending.add_metric(self.labels, r.pending)
        yield pending


def serve(collector: AgentCollector, port: int, addr: str) -> tuple[Any, int]:
    """Serve the collector (alone: no process metrics of a short-lived wrapper) on ``addr:port``."""
    registry = CollectorRegistry(auto_describe=False)
    registry.register(collector)
    server, _thread = start_http_server(port, addr=addr, registry=registry)
    return server, server.server_port
