from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="ApplicationImportResult")


@_attrs_define
class ApplicationImportResult:
    """The stored application plus what the reader flagged while accepting the file.

    Attributes:
        id (int):
        name (str):
        dag (Any): the DAG as continuum.dag/v1
        source_format (str):
        task_count (int):
        edge_count (int):
        created (datetime.datetime):
        updated (datetime.datetime):
        warnings (list[str]):
        fleet (str | Unset):
        description (str | Unset):
    """

    id: int
    name: str
    dag: Any
    source_format: str
    task_count: int
    edge_count: int
    created: datetime.datetime
    updated: datetime.datetime
    warnings: list[str]
    fleet: str | Unset = UNSET
    description: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        name = self.name

        dag = self.dag

        source_format = self.source_format

        task_count = self.task_count

        edge_count = self.edge_count

        created = self.created.isoformat()

        updated = self.updated.isoformat()

        warnings = self.warnings

        fleet = self.fleet

        description = self.description

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "name": name,
                "dag": dag,
                "source_format": source_format,
                "task_count": task_count,
                "edge_count": edge_count,
                "created": created,
                "updated": updated,
                "warnings": warnings,
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
        id = d.pop("id")

        name = d.pop("name")

        dag = d.pop("dag")

        source_format = d.pop("source_format")

        task_count = d.pop("task_count")

        edge_count = d.pop("edge_count")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        updated = datetime.datetime.fromisoformat(d.pop("updated"))

        warnings = cast(list[str], d.pop("warnings"))

        fleet = d.pop("fleet", UNSET)

        description = d.pop("description", UNSET)

        application_import_result = cls(
            id=id,
            name=name,
            dag=dag,
            source_format=source_format,
            task_count=task_count,
            edge_count=edge_count,
            created=created,
            updated=updated,
            warnings=warnings,
            fleet=fleet,
            description=description,
        )

        application_import_result.additional_properties = d
        return application_import_result

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
