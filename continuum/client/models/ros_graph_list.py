from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.source_format_enum import SourceFormatEnum, check_source_format_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="RosGraphList")


@_attrs_define
class RosGraphList:
    """A ROS graph; PATCH edits levels, topic rates and message sizes, node profiles and package sizes.

    ``levels``: ``{ros node: level or null}``; ``topics``: ``{topic: {rate_hz | period_ms |
    publisher_rates_hz, msg_bytes, msg_type}}``; ``nodes``: ``{ros node: {level, context, origin, cpu,
    memory_mib, packages}}``; ``packages``: ``{package: size_mib | {size_mib, archs, apt} | null}``.

        Attributes:
            id (int):
            fleet (str):
            name (str):
            source_format (SourceFormatEnum): * `rosgraph` - continuum.rosgraph/v1
                * `autoware` - Autoware reference system JSON
                * `irobot` - iRobot ros2-performance topology
                * `dot` - Graphviz .dot (rqt_graph)
            node_count (int):
            topic_count (int):
            created (datetime.datetime):
            description (str | Unset):
    """

    id: int
    fleet: str
    name: str
    source_format: SourceFormatEnum
    node_count: int
    topic_count: int
    created: datetime.datetime
    description: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        fleet = self.fleet

        name = self.name

        source_format: str = self.source_format

        node_count = self.node_count

        topic_count = self.topic_count

        created = self.created.isoformat()

        description = self.description

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "fleet": fleet,
                "name": name,
                "source_format": source_format,
                "node_count": node_count,
                "topic_count": topic_count,
                "created": created,
            }
        )
        if description is not UNSET:
            field_dict["description"] = description

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        fleet = d.pop("fleet")

        name = d.pop("name")

        source_format = check_source_format_enum(d.pop("source_format"))

        node_count = d.pop("node_count")

        topic_count = d.pop("topic_count")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        description = d.pop("description", UNSET)

        ros_graph_list = cls(
            id=id,
            fleet=fleet,
            name=name,
            source_format=source_format,
            node_count=node_count,
            topic_count=topic_count,
            created=created,
            description=description,
        )

        ros_graph_list.additional_properties = d
        return ros_graph_list

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
