from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="PatchedAssertionRequest")


@_attrs_define
class PatchedAssertionRequest:
    """``fleet`` defaults to the token's fleet, or to the caller's only fleet.

    Attributes:
        fleet (str | Unset):
        name (str | Unset):
        text (str | Unset): e.g. G(speed > 0 -> F[0,5000](arrived)); intervals in ms
        constants (Any | Unset): named numbers, e.g. {"timeout": 5000}
        description (str | Unset):
    """

    fleet: str | Unset = UNSET
    name: str | Unset = UNSET
    text: str | Unset = UNSET
    constants: Any | Unset = UNSET
    description: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        fleet = self.fleet

        name = self.name

        text = self.text

        constants = self.constants

        description = self.description

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if name is not UNSET:
            field_dict["name"] = name
        if text is not UNSET:
            field_dict["text"] = text
        if constants is not UNSET:
            field_dict["constants"] = constants
        if description is not UNSET:
            field_dict["description"] = description

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        fleet = d.pop("fleet", UNSET)

        name = d.pop("name", UNSET)

        text = d.pop("text", UNSET)

        constants = d.pop("constants", UNSET)

        description = d.pop("description", UNSET)

        patched_assertion_request = cls(
            fleet=fleet,
            name=name,
            text=text,
            constants=constants,
            description=description,
        )

        patched_assertion_request.additional_properties = d
        return patched_assertion_request

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
