"""Live pod state in pages: the one JSON shape, partial and script that every domain page uses.

The domain apps own the rows (a schedule's assignments, a placement's Deployments, RT-Kube's pods) whose live
state the cluster's watcher stores (``apps.clusters.live``); each turns its rows into :class:`LivePod` and
answers :func:`live_response` from a small view. A page includes ``ui/includes/live_pods.html`` with that
view's URL; ``static/js/live-pods.js`` polls it and redraws the table, so phases and events follow the
cluster without a reload. No domain import here: the apps bring the data.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from dataclasses import asdict, dataclass
from datetime import datetime
from typing import Any

from django.http import JsonResponse

#: Most pods one answer lists (the rest are counted): a 10,000-task schedule's pods stay a summary.
LIMIT = 200


@dataclass(frozen=True)
class LivePod:
    """One pod as a page shows it: what it is, where the plan put it and where it runs now."""

    label: str  # what the pod is for: "task t3 (frame 0)", "container slam"
    pod: str = ""  # the pod's name ('' before a push)
    planned: str = ""  # the node of the plan
    node: str = ""  # the node it is bound to now ('' while pending or unknown)
    phase: str = ""  # Kubernetes phase: Pending, Running, Succeeded, Failed, Unknown, Deleted ('' not seen)
    event: str = ""  # its newest Event, "Reason: message"
    at: datetime | None = None  # when the watcher last stored a change

    @classmethod
    def from_row(cls, row: Any, label: str, planned: str = "") -> LivePod:
        """From a domain row holding the watcher's fields (``pod_name``, ``pod_node``, ``pod_phase``,
        ``pod_event``, ``pod_state_at``: a schedule's assignment, a placement's Deployment)."""
        return cls(
            label=label,
            pod=row.pod_name,
            planned=planned,
            node=row.pod_node,
            phase=row.pod_phase,
            event=row.pod_event,
            at=row.pod_state_at,
        )

    @property
    def moved(self) -> bool:
        """Runs on another node than planned."""
        return bool(self.planned and self.node and self.node != self.planned)


def live_payload(pods: Iterable[LivePod], total: int | None = None, empty: str = "") -> dict:
    """The JSON the partial's script reads: ``pods`` (at most :data:`LIMIT`), ``total``, phase counts,
    how many run off-plan, and the text to show when there is none."""
    shown = list(pods)[:LIMIT]
    rows = []
    for pod in shown:
        row = asdict(pod)
        row["at"] = pod.at.isoformat() if pod.at else None
        row["moved"] = pod.moved
        rows.append(row)
    return {
        "pods": rows,
        "total": len(shown) if total is None else total,
        "phases": dict(Counter(p.phase or "not seen" for p in shown)),
        "moved": sum(p.moved for p in shown),
        "empty": empty,
    }


def live_response(pods: Iterable[LivePod], total: int | None = None, empty: str = "") -> JsonResponse:
    response = JsonResponse(live_payload(pods, total, empty))
    response["Cache-Control"] = "no-store"  # always the watcher's newest
    return response
