from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="AssertionRequest")


@_attrs_define
class AssertionRequest:
    """``fleet`` defaults to the token's fleet, or to the caller's only fleet.

    Attributes:
        name (str):
        text (str): e.g. G(speed > 0 -> F[0,5000](arrived)); intervals in ms
        fleet (str | Unset):
        constants (Any | Unset): named numbers, e.g. {"timeout": 5000}
        description (str | Unset):
    """

    name: str
    text: str
    fleet: str | Unset = UNSET
    constants: Any | Unset = UNSET
    description: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        name = self.name

        text = self.text

        fleet = self.fleet

        constants = self.constants

        description = self.description

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "name": name,
                "text": text,
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
        name = d.pop("name")

        text = d.pop("text")

        fleet = d.pop("fleet", UNSET)

        constants = d.pop("constants", UNSET)

        description = d.pop("description", UNSET)

        assertion_request = cls(
            name=name,
            text=text,
            fleet=fleet,
            constants=constants,
            description=description,
        )

        assertion_request.additional_properties = d
        return assertion_request

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
