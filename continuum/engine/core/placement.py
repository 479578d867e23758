"""The placement type: items (containers, RT containers) put on cluster nodes, with the reason for each.

This is what the node-level placers return (super-clustering, thesis 3.3.1; RT-Kube, 3.4) and what the
database, the "why here?" views, the API and the Kubernetes gateway read. Like kube-scheduler-simulator,
every decision keeps, for each node, the filter that rejected it or the score each policy gave it.
DAG schedules with start and finish times use :class:`~continuum.engine.core.schedule.Schedule` instead.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Decision", "NodeVerdict", "PlacementPlan"]

_PLAN_KEYS = frozenset({"policy", "placements", "pending", "decisions", "params"})


@dataclass(frozen=True)
class NodeVerdict:
    """One node's outcome for one item: rejected by a filter, or scored by the policies."""

    node: str
    #: Name of the filter that rejected the node; ``None`` when it passed every filter.
    rejected_by: str | None = None
    reason: str = ""
    #: Policy name -> score of this node (after normalisation), when it passed the filters.
    scores: dict[str, float] = field(default_factory=dict)
    total: float | None = None

    def to_dict(self) -> dict[str, Any]:
        return {
            "node": self.node,
            "rejected_by": self.rejected_by,
            "reason": self.reason,
            "scores": dict(self.scores),
            "total": self.total,
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> NodeVerdict:
        return cls(
            node=data["node"],
            rejected_by=data.get("rejected_by"),
            reason=data.get("reason", ""),
            scores=dict(data.get("scores") or {}),
            total=data.get("total"),
        )


@dataclass(frozen=True)
class Decision:
    """Where one item went (``node``), or ``None`` when it stays pending, and why."""

    item: str
    node: str | None
    score: float | None = None
    #: A tuple, or a sequence that builds its verdicts when first read (super-clustering).
    verdicts: Sequence[NodeVerdict] = ()
    #: Filter name -> how many nodes it rejected, when ``verdicts`` is a bounded sample of the nodes (the
    #: vectorised RT-Kube keeps the top candidates and a few examples per filter); empty when every node is in
    #: ``verdicts``.
    rejections: Mapping[str, int] = field(default_factory=dict)

    @property
    def pending(self) -> bool:
        return self.node is None

    def reasons(self) -> dict[str, str]:
        """Node -> why it was not chosen (the filter's reason), for the contracts' ``pending`` lists."""
        return {v.node: v.reason or (v.rejected_by or "") for v in self.verdicts if v.rejected_by}

    def to_dict(self) -> dict[str, Any]:
        doc: dict[str, Any] = {
            "item": self.item,
            "node": self.node,
            "score": self.score,
            "verdicts": [v.to_dict() for v in self.verdicts],
        }
        if self.rejections:
            doc["rejections"] = dict(self.rejections)
        return doc

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Decision:
        return cls(
            item=data["item"],
            node=data.get("node"),
            score=data.get("score"),
            verdicts=tuple(NodeVerdict.from_dict(v) for v in data.get("verdicts") or ()),
            rejections=dict(data.get("rejections") or {}),
        )


@dataclass
class PlacementPlan:
    """All decisions of one placement run, in decision order."""

    policy: str
    decisions: list[Decision]
    params: dict[str, Any] = field(default_factory=dict)
    metrics: dict[str, Any] = field(default_factory=dict)

    def placed(self) -> dict[str, str]:
        return {d.item: d.node for d in self.decisions if d.node is not None}

    def decision(self, item: str) -> Decision | None:
        """The decision about ``item`` (``None`` when the plan has none)."""
        return next((d for d in self.decisions if d.item == item), None)

    def to_dict(self, item_key: str = "container") -> dict[str, Any]:
        """The contracts' shape (``placements``, ``pending``) plus the full explanation.

        The metrics are written at the top level, so a metric must not be called like one of the plan's own
        keys (``policy``, ``placements``, ``pending``, ``decisions``, ``params``).
        """
        return {
            "policy": self.policy,
            "placements": [
                {item_key: d.item, "node": d.node, "score": d.score} for d in self.decisions if not d.pending
            ],
            "pending": [self._pending(d, item_key) for d in self.decisions if d.pending],
            "decisions": [d.to_dict() for d in self.decisions],
            "params": dict(self.params),
            **self.metrics,
        }

    @staticmethod
    def _pending(d: Decision, item_key: str) -> dict[str, Any]:
        # A bounded decision lists a few example nodes in ``reasons``: the count of nodes per filter says
        # what the examples stand for (kube-scheduler's "0/5000 nodes are available: ..." in numbers).
        doc: dict[str, Any] = {item_key: d.item, "reasons": d.reasons()}
        if d.rejections:
            doc["rejections"] = dict(d.rejections)
        return doc

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, ignore: tuple[str, ...] = ()) -> PlacementPlan:
        """The plan :meth:`to_dict` wrote (``from_dict(plan.to_dict()) == plan``, whatever the item key).

        ``placements`` and ``pending`` are derived from ``decisions`` and not read; every other top-level key
        is a metric, except the ones named in ``ignore`` (what a caller stored beside the plan).
        """
        if not isinstance(data, Mapping) or not isinstance(data.get("decisions"), list):
            raise ValueError("a placement plan needs a 'decisions' list")
        return cls(
            policy=data.get("policy", ""),
            decisions=[Decision.from_dict(d) for d in data["decisions"]],
            params=dict(data.get("params") or {}),
            metrics={k: v for k, v in data.items() if k not in _PLAN_KEYS and k not in ignore},
        )
