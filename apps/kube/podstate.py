"""A pod's live state as plain data, read from the server's JSON of a watched pod or Event.

The watcher of a cluster (``apps.clusters.live``) follows pods and their core/v1 Events with
:func:`apps.kube.watch.follow`; these functions turn what it receives into :class:`PodState` and
:class:`PodEvent`, which the apps that own pods store (no Kubernetes model objects leave the gateway).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from datetime import datetime
from typing import Any

#: The phase stored for a pod the API deleted.
DELETED = "Deleted"


@dataclass(frozen=True)
class PodEvent:
    """The newest Event about a pod: its reason and message, when it happened (ISO 8601) and its type."""

    reason: str
    message: str
    at: str = ""
    type: str = ""

    def text(self, limit: int = 500) -> str:
        """``"Reason: message"``, cut to ``limit`` characters."""
        text = f"{self.reason}: {self.message}" if self.message else self.reason
        return text[:limit]

    def newer_than(self, other: PodEvent | None) -> bool:
        """Whether this event is at least as recent as ``other`` (ties: the later one seen wins)."""
        return other is None or _instant(self.at) >= _instant(other.at)


@dataclass(frozen=True)
class PodState:
    """One pod as the watch last saw it: identity, labels, phase, node and its newest event."""

    namespace: str
    name: str
    uid: str = ""
    labels: dict[str, str] = field(default_factory=dict)
    annotations: dict[str, str] = field(default_factory=dict)
    phase: str = ""
    node: str = ""
    created: str = ""
    terminating: bool = False
    deleted: bool = False
    event: PodEvent | None = None

    @property
    def key(self) -> tuple[str, str]:
        return (self.namespace, self.name)

    def with_event(self, event: PodEvent | None) -> PodState:
        return replace(self, event=event)

    def signature(self) -> tuple:
        """What the stored state depends on: an unchanged signature needs no write."""
        return (self.uid, self.phase, self.node, self.terminating, self.deleted, self.event)


def _instant(value: str) -> datetime:
    if not value:
        return datetime.min
    try:
        parsed = datetime.fromisoformat(value.replace("Z", "+00:00"))
    except ValueError:
        return datetime.min
    return parsed.replace(tzinfo=None)


def pod_state(obj: dict[str, Any], *, deleted: bool = False) -> PodState:
    """The state of a pod from its JSON (``deleted``: the watch said DELETED)."""
    meta = obj.get("metadata") or {}
    spec = obj.get("spec") or {}
    status = obj.get("status") or {}
    return PodState(
        namespace=meta.get("namespace") or "",
        name=meta.get("name") or "",
        uid=meta.get("uid") or "",
        labels=dict(meta.get("labels") or {}),
        annotations=dict(meta.get("annotations") or {}),
        phase=DELETED if deleted else (status.get("phase") or ""),
        node=spec.get("nodeName") or "",
        created=meta.get("creationTimestamp") or "",
        terminating=bool(meta.get("deletionTimestamp")),
        deleted=deleted,
    )


def event_of(obj: dict[str, Any]) -> tuple[tuple[str, str], str, PodEvent] | None:
    """``((namespace, pod name), pod uid, event)`` of a core/v1 Event about a pod; ``None`` for another kind."""
    involved = obj.get("involvedObject") or {}
    if involved.get("kind") != "Pod" or not involved.get("name"):
        return None
    meta = obj.get("metadata") or {}
    namespace = involved.get("namespace") or meta.get("namespace") or ""
    at = (
        obj.get("lastTimestamp")
        or obj.get("eventTime")
        or (obj.get("series") or {}).get("lastObservedTime")
        or obj.get("firstTimestamp")
        or meta.get("creationTimestamp")
        or ""
    )
    event = PodEvent(
        reason=obj.get("reason") or "",
        message=(obj.get("message") or "").strip(),
        at=at,
        type=obj.get("type") or "",
    )
    return (namespace, involved["name"]), involved.get("uid") or "", event
