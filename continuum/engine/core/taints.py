"""Kubernetes taints and tolerations, as every node-level placer reads them.

One definition for the container placement of super-clustering (thesis 3.3.1), the RT-Kube filter (3.4,
which relies on the ``RealTime=RT:NoSchedule`` taint) and the cluster reader. A taint may expire (``until``),
which is how the RT-Kube monitor's timed taint is modelled.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from continuum.engine.core.errors import InputError

__all__ = [
    "NOT_READY",
    "REALTIME",
    "STATUS_TAINTS",
    "TAINT_EFFECTS",
    "TOLERATION_OPERATORS",
    "UNREACHABLE",
    "Taint",
    "Toleration",
    "status_taint",
    "untolerated",
]

TAINT_EFFECTS = ("NoSchedule", "PreferNoSchedule", "NoExecute")
TOLERATION_OPERATORS = ("Equal", "Exists")


@dataclass(frozen=True)
class Taint:
    key: str
    value: str = ""
    effect: str = "NoSchedule"
    #: Time (input unit) after which the taint is gone; ``None`` = permanent.
    until: float | None = None

    def __str__(self) -> str:
        return f"{self.key}={self.value}:{self.effect}" if self.value else f"{self.key}:{self.effect}"

    def active(self, now: float | None) -> bool:
        return self.until is None or now is None or now < self.until

    def to_dict(self) -> dict[str, Any]:
        doc: dict[str, Any] = {"key": self.key, "value": self.value, "effect": self.effect}
        if self.until is not None:
            doc["until"] = self.until
        return doc

    @classmethod
    def parse(cls, raw: Any, where: str) -> Taint:
        """``"key=value:Effect"`` (kubectl's form) or ``{"key", "value", "effect"[, "until"]}``."""
        if isinstance(raw, str):
            head, sep, effect = raw.rpartition(":")
            if not sep or not head:
                raise InputError(f"{where}: taint {raw!r} is not key=value:Effect", "taints")
            key, _, value = head.partition("=")
            raw = {"key": key, "value": value, "effect": effect}
        if not isinstance(raw, Mapping) or not isinstance(raw.get("key"), str) or not raw["key"]:
            raise InputError(f"{where}: taint {raw!r} needs a 'key' (or is a 'key=value:Effect' string)", "taints")
        effect = raw.get("effect") or "NoSchedule"
        if effect not in TAINT_EFFECTS:
            raise InputError(
                f"{where}: taint has unknown effect {effect!r} (one of {', '.join(TAINT_EFFECTS)})", "taints"
            )
        until = raw.get("until")
        if until is not None and (
            isinstance(until, bool) or not isinstance(until, int | float) or not math.isfinite(until)
        ):
            raise InputError(f"{where}: taint 'until' must be a finite number, got {until!r}", "taints")
        return cls(raw["key"], str(raw.get("value") or ""), effect, None if until is None else float(until))


@dataclass(frozen=True)
class Toleration:
    key: str = ""
    operator: str = "Equal"
    value: str = ""
    #: Empty = tolerates every effect.
    effect: str = ""

    def tolerates(self, taint: Taint) -> bool:
        """Kubernetes' rule: an empty key with ``Exists`` tolerates everything."""
        if self.effect and self.effect != taint.effect:
            return False
        if not self.key:
            return self.operator == "Exists"
        if self.key != taint.key:
            return False
        return self.operator == "Exists" or self.value == taint.value

    def to_dict(self) -> dict[str, str]:
        doc = {"key": self.key, "operator": self.operator}
        if self.operator == "Equal":
            doc["value"] = self.value
        if self.effect:
            doc["effect"] = self.effect
        return doc

    @classmethod
    def parse(cls, raw: Any, where: str) -> Toleration:
        if not isinstance(raw, Mapping):
            raise InputError(f"{where}: toleration must be an object", "tolerations")
        op = raw.get("operator", "Equal")
        if op not in TOLERATION_OPERATORS:
            raise InputError(f"{where}: toleration operator {op!r} is not Equal or Exists", "tolerations")
        return cls(str(raw.get("key") or ""), op, str(raw.get("value") or ""), str(raw.get("effect") or ""))


def untolerated(taints: Iterable[Taint], tolerations: Iterable[Toleration], now: float | None = None) -> list[Taint]:
    """The scheduling taints (NoSchedule/NoExecute) of a node that no toleration matches."""
    tols = list(tolerations)
    return [
        t
        for t in taints
        if t.effect != "PreferNoSchedule" and t.active(now) and not any(tol.tolerates(t) for tol in tols)
    ]


#: RT-Kube's taint of an RT-only node (thesis 3.4): an RT node whose document gives no ``taints`` carries it.
REALTIME = Taint("RealTime", "RT", "NoSchedule")


#: The taints Kubernetes puts on a node that is not Ready (the node lifecycle controller's NoSchedule taints),
#: by the node's Ready condition: ``NotReady`` (condition False) and ``Unknown`` (no heartbeat).
NOT_READY = Taint("node.kubernetes.io/not-ready", "", "NoSchedule")
UNREACHABLE = Taint("node.kubernetes.io/unreachable", "", "NoSchedule")
STATUS_TAINTS = {"NotReady": NOT_READY, "Unknown": UNREACHABLE}


def status_taint(status: str) -> Taint | None:
    """The taint of a node whose Ready condition is ``status`` (``None`` for ``Ready``)."""
    return STATUS_TAINTS.get(status)
