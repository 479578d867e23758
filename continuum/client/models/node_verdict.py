from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

if TYPE_CHECKING:
    from ..models.node_verdict_scores import NodeVerdictScores


T = TypeVar("T", bound="NodeVerdict")


@_attrs_define
class NodeVerdict:
    """The base of every plain serializer of the API.

    Attributes:
        node (str):
        rejected_by (None | str): the filter that rejected the node, or null
        reason (str):
        scores (NodeVerdictScores):
        total (float | None):
    """

    node: str
    rejected_by: str | None
    reason: str
    scores: NodeVerdictScores
    total: float | None
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        node = self.node

        rejected_by: str | None
        rejected_by = self.rejected_by

        reason = self.reason

        scores = self.scores.to_dict()

        total: float | None
        total = self.total

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "node": node,
                "rejected_by": rejected_by,
                "reason": reason,
                "scores": scores,
                "total": total,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.node_verdict_scores import NodeVerdictScores

        d = dict(src_dict)
        node = d.pop("node")

        def _parse_rejected_by(data: object) -> str | None:
            if data is None:
                return data
            return cast(str | None, data)

        rejected_by = _parse_rejected_by(d.pop("rejected_by"))

        reason = d.pop("reason")

        scores = NodeVerdictScores.from_dict(d.pop("scores"))

        def _parse_total(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        total = _parse_total(d.pop("total"))

        node_verdict = cls(
            node=node,
            rejected_by=rejected_by,
            reason=reason,
            scores=scores,
            total=total,
        )

        node_verdict.additional_properties = d
        return node_verdict

    @property
    def additional_keys(self) -> list[str]:
        return list(self.additional_properties.keys())

    def __getitem__(self, key: str) -> Any:
        return self.additional_properties[key]

    def __setitem__(self, key: str, value: Any) -> None:
        self.additional_properties[key] = value

    def __delitem__(self, key: str) -> None:
        del self.additional_properties[key]

    def __contains__(self, key: str) -> bool:
        return key in self.additional_properties
