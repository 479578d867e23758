from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

T = TypeVar("T", bound="ClusteringList")


@_attrs_define
class ClusteringList:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        fleet (str):
        rosgraph (int):
        rosgraph_name (str):
        requested_containers (int):
        container_count (int):
        inter_container_bandwidth (float): bytes/s left between containers
        intra_container_bandwidth (float): bytes/s kept inside containers
        disk_before_mib (float | None):
        disk_after_mib (float | None):
        created (datetime.datetime):
    """

    id: int
    fleet: str
    rosgraph: int
    rosgraph_name: str
    requested_containers: int
    container_count: int
    inter_container_bandwidth: float
    intra_container_bandwidth: float
    disk_before_mib: float | None
    disk_after_mib: float | None
    created: datetime.datetime
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        fleet = self.fleet

        rosgraph = self.rosgraph

        rosgraph_name = self.rosgraph_name

        requested_containers = self.requested_containers

        container_count = self.container_count

        inter_container_bandwidth = self.inter_container_bandwidth

        intra_container_bandwidth = self.intra_container_bandwidth

        disk_before_mib: float | None
        disk_before_mib = self.disk_before_mib

        disk_after_mib: float | None
        disk_after_mib = self.disk_after_mib

        created = self.created.isoformat()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "fleet": fleet,
                "rosgraph": rosgraph,
                "rosgraph_name": rosgraph_name,
                "requested_containers": requested_containers,
                "container_count": container_count,
                "inter_container_bandwidth": inter_container_bandwidth,
                "intra_container_bandwidth": intra_container_bandwidth,
                "disk_before_mib": disk_before_mib,
                "disk_after_mib": disk_after_mib,
                "created": created,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        fleet = d.pop("fleet")

        rosgraph = d.pop("rosgraph")

        rosgraph_name = d.pop("rosgraph_name")

        requested_containers = d.pop("requested_containers")

        container_count = d.pop("container_count")

        inter_container_bandwidth = d.pop("inter_container_bandwidth")

        intra_container_bandwidth = d.pop("intra_container_bandwidth")

        def _parse_disk_before_mib(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        disk_before_mib = _parse_disk_before_mib(d.pop("disk_before_mib"))

        def _parse_disk_after_mib(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        disk_after_mib = _parse_disk_after_mib(d.pop("disk_after_mib"))

        created = datetime.datetime.fromisoformat(d.pop("created"))

        clustering_list = cls(
            id=id,
            fleet=fleet,
            rosgraph=rosgraph,
            rosgraph_name=rosgraph_name,
            requested_containers=requested_containers,
            container_count=container_count,
            inter_container_bandwidth=inter_container_bandwidth,
            intra_container_bandwidth=intra_container_bandwidth,
            disk_before_mib=disk_before_mib,
            disk_after_mib=disk_after_mib,
            created=created,
        )

        clustering_list.additional_properties = d
        return clustering_list

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
