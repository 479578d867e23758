from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="MonitorRequest")


@_attrs_define
class MonitorRequest:
    """``fleet`` defaults to the token's fleet, or to the caller's only fleet.

    Attributes:
        assertion (int):
        cluster (int):
        name (str):
        fleet (str | Unset):
        tolerant (bool | Unset): may drop old events and reset under overload (soft properties only, §11.2)
        node (int | None | Unset):
    """

    assertion: int
    cluster: int
    name: str
    fleet: str | Unset = UNSET
    tolerant: bool | Unset = UNSET
    node: int | Unset | None = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        assertion = self.assertion

        cluster = self.cluster

        name = self.name

        fleet = self.fleet

        tolerant = self.tolerant

        node: int | Unset | None
        node = UNSET if isinstance(self.node, Unset) else self.node

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "assertion": assertion,
                "cluster": cluster,
                "name": name,
            }
        )
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if tolerant is not UNSET:
            field_dict["tolerant"] = tolerant
        if node is not UNSET:
            field_dict["node"] = node

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        assertion = d.pop("assertion")

        cluster = d.pop("cluster")

        name = d.pop("name")

        fleet = d.pop("fleet", UNSET)

        tolerant = d.pop("tolerant", UNSET)

        def _parse_node(data: object) -> int | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | Unset | None, data)

        node = _parse_node(d.pop("node", UNSET))

        monitor_request = cls(
            assertion=assertion,
            cluster=cluster,
            name=name,
            fleet=fleet,
            tolerant=tolerant,
            node=node,
        )

        monitor_request.additional_properties = d
        return monitor_request

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
