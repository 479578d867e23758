from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

if TYPE_CHECKING:
    from ..models.node_verdict import NodeVerdict


T = TypeVar("T", bound="WhyNot")


@_attrs_define
class WhyNot:
    """A decision's full explanation on demand, computed against the cluster as it is now.

    Attributes:
        decision (int):
        pod (str): namespace/name
        chosen (None | str): the node the decision chose, or null (pending)
        as_of (datetime.datetime):
        nodes (int): nodes in the cluster
        verdicts (list[NodeVerdict]):
    """

    decision: int
    pod: str
    chosen: str | None
    as_of: datetime.datetime
    nodes: int
    verdicts: list[NodeVerdict]
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        decision = self.decision

        pod = self.pod

        chosen: str | None
        chosen = self.chosen

        as_of = self.as_of.isoformat()

        nodes = self.nodes

        verdicts = []
        for verdicts_item_data in self.verdicts:
            verdicts_item = verdicts_item_data.to_dict()
            verdicts.append(verdicts_item)

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "decision": decision,
                "pod": pod,
                "chosen": chosen,
                "as_of": as_of,
                "nodes": nodes,
                "verdicts": verdicts,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.node_verdict import NodeVerdict

        d = dict(src_dict)
        decision = d.pop("decision")

        pod = d.pop("pod")

        def _parse_chosen(data: object) -> str | None:
            if data is None:
                return data
            return cast(str | None, data)

        chosen = _parse_chosen(d.pop("chosen"))

        as_of = datetime.datetime.fromisoformat(d.pop("as_of"))

        nodes = d.pop("nodes")

        verdicts = []
        _verdicts = d.pop("verdicts")
        for verdicts_item_data in _verdicts:
            verdicts_item = NodeVerdict.from_dict(verdicts_item_data)

            verdicts.append(verdicts_item)

        why_not = cls(
            decision=decision,
            pod=pod,
            chosen=chosen,
            as_of=as_of,
            nodes=nodes,
            verdicts=verdicts,
        )

        why_not.additional_properties = d
        return why_not

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
