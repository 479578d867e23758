from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="Assertion")


@_attrs_define
class Assertion:
    """``fleet`` defaults to the token's fleet, or to the caller's only fleet.

    Attributes:
        id (int):
        name (str):
        text (str): e.g. G(speed > 0 -> F[0,5000](arrived)); intervals in ms
        skeleton (str): the monitor's form with placeholders (Fig. 3.41)
        placeholders (Any):
        variables (Any): the signals the monitor subscribes to
        status (str):
        monitor_count (int):
        created (datetime.datetime):
        updated (datetime.datetime):
        fleet (str | Unset):
        constants (Any | Unset): named numbers, e.g. {"timeout": 5000}
        description (str | Unset):
    """

    id: int
    name: str
    text: str
    skeleton: str
    placeholders: Any
    variables: Any
    status: str
    monitor_count: int
    created: datetime.datetime
    updated: datetime.datetime
    fleet: str | Unset = UNSET
    constants: Any | Unset = UNSET
    description: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        name = self.name

        text = self.text

        skeleton = self.skeleton

        placeholders = self.placeholders

        variables = self.variables

        status = self.status

        monitor_count = self.monitor_count

        created = self.created.isoformat()

        updated = self.updated.isoformat()

        fleet = self.fleet

        constants = self.constants

        description = self.description

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "name": name,
                "text": text,
                "skeleton": skeleton,
                "placeholders": placeholders,
                "variables": variables,
                "status": status,
                "monitor_count": monitor_count,
                "created": created,
                "updated": updated,
            }
        )
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if constants is not UNSET:
            field_dict["constants"] = constants
        if description is not UNSET:
            field_dict["description"] = description

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        name = d.pop("name")

        text = d.pop("text")

        skeleton = d.pop("skeleton")

        placeholders = d.pop("placeholders")

        variables = d.pop("variables")

        status = d.pop("status")

        monitor_count = d.pop("monitor_count")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        updated = datetime.datetime.fromisoformat(d.pop("updated"))

        fleet = d.pop("fleet", UNSET)

        constants = d.pop("constants", UNSET)

        description = d.pop("description", UNSET)

        assertion = cls(
            id=id,
            name=name,
            text=text,
            skeleton=skeleton,
            placeholders=placeholders,
            variables=variables,
            status=status,
            monitor_count=monitor_count,
            created=created,
            updated=updated,
            fleet=fleet,
            constants=constants,
            description=description,
        )

        assertion.additional_properties = d
        return assertion

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
