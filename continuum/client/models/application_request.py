from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="ApplicationRequest")


@_attrs_define
class ApplicationRequest:
    """An application with its DAG in ``continuum.dag/v1``; a bad DAG is rejected whole, naming the culprit.

    Attributes:
        name (str):
        dag (Any): the DAG as continuum.dag/v1
        fleet (str | Unset):
        description (str | Unset):
    """

    name: str
    dag: Any
    fleet: str | Unset = UNSET
    description: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        name = self.name

        dag = self.dag

        fleet = self.fleet

        description = self.description

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "name": name,
                "dag": dag,
            }
        )
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if description is not UNSET:
            field_dict["description"] = description

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        name = d.pop("name")

        dag = d.pop("dag")

        fleet = d.pop("fleet", UNSET)

        description = d.pop("description", UNSET)

        application_request = cls(
            name=name,
            dag=dag,
            fleet=fleet,
            description=description,
        )

        application_request.additional_properties = d
        return application_request

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
