from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="PatchedApplicationRequest")


@_attrs_define
class PatchedApplicationRequest:
    """An application with its DAG in ``continuum.dag/v1``; a bad DAG is rejected whole, naming the culprit.

    Attributes:
        fleet (str | Unset):
        name (str | Unset):
        description (str | Unset):
        dag (Any | Unset): the DAG as continuum.dag/v1
    """

    fleet: str | Unset = UNSET
    name: str | Unset = UNSET
    description: str | Unset = UNSET
    dag: Any | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        fleet = self.fleet

        name = self.name

        description = self.description

        dag = self.dag

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if name is not UNSET:
            field_dict["name"] = name
        if description is not UNSET:
            field_dict["description"] = description
        if dag is not UNSET:
            field_dict["dag"] = dag

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        fleet = d.pop("fleet", UNSET)

        name = d.pop("name", UNSET)

        description = d.pop("description", UNSET)

        dag = d.pop("dag", UNSET)

        patched_application_request = cls(
            fleet=fleet,
            name=name,
            description=description,
            dag=dag,
        )

        patched_application_request.additional_properties = d
        return patched_application_request

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
