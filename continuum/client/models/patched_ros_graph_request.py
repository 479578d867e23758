from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.patched_ros_graph_request_levels import PatchedRosGraphRequestLevels
    from ..models.patched_ros_graph_request_nodes import PatchedRosGraphRequestNodes
    from ..models.patched_ros_graph_request_packages import PatchedRosGraphRequestPackages
    from ..models.patched_ros_graph_request_topics import PatchedRosGraphRequestTopics


T = TypeVar("T", bound="PatchedRosGraphRequest")


@_attrs_define
class PatchedRosGraphRequest:
    """A ROS graph; PATCH edits levels, topic rates and message sizes, node profiles and package sizes.

    ``levels``: ``{ros node: level or null}``; ``topics``: ``{topic: {rate_hz | period_ms |
    publisher_rates_hz, msg_bytes, msg_type}}``; ``nodes``: ``{ros node: {level, context, origin, cpu,
    memory_mib, packages}}``; ``packages``: ``{package: size_mib | {size_mib, archs, apt} | null}``.

        Attributes:
            name (str | Unset):
            description (str | Unset):
            levels (PatchedRosGraphRequestLevels | Unset): ROS node -> level (null: proposed)
            topics (PatchedRosGraphRequestTopics | Unset): topic -> {rate_hz, msg_bytes, ...}
            nodes (PatchedRosGraphRequestNodes | Unset): ROS node -> {cpu, pin, ...}
            packages (PatchedRosGraphRequestPackages | Unset): package -> size_mib or object
    """

    name: str | Unset = UNSET
    description: str | Unset = UNSET
    levels: PatchedRosGraphRequestLevels | Unset = UNSET
    topics: PatchedRosGraphRequestTopics | Unset = UNSET
    nodes: PatchedRosGraphRequestNodes | Unset = UNSET
    packages: PatchedRosGraphRequestPackages | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        name = self.name

        description = self.description

        levels: dict[str, Any] | Unset = UNSET
        if not isinstance(self.levels, Unset):
            levels = self.levels.to_dict()

        topics: dict[str, Any] | Unset = UNSET
        if not isinstance(self.topics, Unset):
            topics = self.topics.to_dict()

        nodes: dict[str, Any] | Unset = UNSET
        if not isinstance(self.nodes, Unset):
            nodes = self.nodes.to_dict()

        packages: dict[str, Any] | Unset = UNSET
        if not isinstance(self.packages, Unset):
            packages = self.packages.to_dict()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if name is not UNSET:
            field_dict["name"] = name
        if description is not UNSET:
            field_dict["description"] = description
        if levels is not UNSET:
            field_dict["levels"] = levels
        if topics is not UNSET:
            field_dict["topics"] = topics
        if nodes is not UNSET:
            field_dict["nodes"] = nodes
        if packages is not UNSET:
            field_dict["packages"] = packages

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.patched_ros_graph_request_levels import PatchedRosGraphRequestLevels
        from ..models.patched_ros_graph_request_nodes import PatchedRosGraphRequestNodes
        from ..models.patched_ros_graph_request_packages import PatchedRosGraphRequestPackages
        from ..models.patched_ros_graph_request_topics import PatchedRosGraphRequestTopics

        d = dict(src_dict)
        name = d.pop("name", UNSET)

        description = d.pop("description", UNSET)

        _levels = d.pop("levels", UNSET)
        levels: PatchedRosGraphRequestLevels | Unset
        levels = UNSET if isinstance(_levels, Unset) else PatchedRosGraphRequestLevels.from_dict(_levels)

        _topics = d.pop("topics", UNSET)
        topics: PatchedRosGraphRequestTopics | Unset
        topics = UNSET if isinstance(_topics, Unset) else PatchedRosGraphRequestTopics.from_dict(_topics)

        _nodes = d.pop("nodes", UNSET)
        nodes: PatchedRosGraphRequestNodes | Unset
        nodes = UNSET if isinstance(_nodes, Unset) else PatchedRosGraphRequestNodes.from_dict(_nodes)

        _packages = d.pop("packages", UNSET)
        packages: PatchedRosGraphRequestPackages | Unset
        packages = UNSET if isinstance(_packages, Unset) else PatchedRosGraphRequestPackages.from_dict(_packages)

        patched_ros_graph_request = cls(
            name=name,
            description=description,
            levels=levels,
            topics=topics,
            nodes=nodes,
            packages=packages,
        )

        patched_ros_graph_request.additional_properties = d
        return patched_ros_graph_request

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
