"""The cluster agent's Prometheus metrics (served by ``manage.py cluster_agent --metrics-port``)."""

from __future__ import annotations

from prometheus_client import Counter

from continuum.metrics import PREFIX

EVENTS = Counter(
    f"{PREFIX}_cluster_agent_events", "Watch events and lists the cluster agent handled", ["cluster", "resource"]
)
HANDLER_ERRORS = Counter(f"{PREFIX}_cluster_agent_handler_errors", "Handler calls that raised", ["handler"])


def event(cluster: int, resource: str) -> None:
    EVENTS.labels(str(cluster), resource).inc()


def handler_failed(name: str) -> None:
    HANDLER_ERRORS.labels(name).inc()
