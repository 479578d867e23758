from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="PatchedMonitorRequest")


@_attrs_define
class PatchedMonitorRequest:
    """``fleet`` defaults to the token's fleet, or to the caller's only fleet.

    Attributes:
        fleet (str | Unset):
        assertion (int | Unset):
        cluster (int | Unset):
        name (str | Unset):
        tolerant (bool | Unset): may drop old events and reset under overload (soft properties only, §11.2)
        node (int | None | Unset):
    """

    fleet: str | Unset = UNSET
    assertion: int | Unset = UNSET
    cluster: int | Unset = UNSET
    name: str | Unset = UNSET
    tolerant: bool | Unset = UNSET
    node: int | Unset | None = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        fleet = self.fleet

        assertion = self.assertion

        cluster = self.cluster

        name = self.name

        tolerant = self.tolerant

        node: int | Unset | None
        node = UNSET if isinstance(self.node, Unset) else self.node

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if assertion is not UNSET:
            field_dict["assertion"] = assertion
        if cluster is not UNSET:
            field_dict["cluster"] = cluster
        if name is not UNSET:
            field_dict["name"] = name
        if tolerant is not UNSET:
            field_dict["tolerant"] = tolerant
        if node is not UNSET:
            field_dict["node"] = node

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        fleet = d.pop("fleet", UNSET)

        assertion = d.pop("assertion", UNSET)

        cluster = d.pop("cluster", UNSET)

        name = d.pop("name", UNSET)

        tolerant = d.pop("tolerant", UNSET)

        def _parse_node(data: object) -> int | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | Unset | None, data)

        node = _parse_node(d.pop("node", UNSET))

        patched_monitor_request = cls(
            fleet=fleet,
            assertion=assertion,
            cluster=cluster,
            name=name,
            tolerant=tolerant,
            node=node,
        )

        patched_monitor_request.additional_properties = d
        return patched_monitor_request

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
