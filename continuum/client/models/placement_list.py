from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

T = TypeVar("T", bound="PlacementList")


@_attrs_define
class PlacementList:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        fleet (str):
        clustering (int | None):
        rosgraph (int | None):
        cluster (int | None):
        policy (str):
        placed_count (int):
        pending_count (int):
        inter_node_bandwidth (float): bytes/s between containers on different nodes
        baseline (Any): the other policy on the same input: policy, inter_node_bandwidth, placements
        created (datetime.datetime):
    """

    id: int
    fleet: str
    clustering: int | None
    rosgraph: int | None
    cluster: int | None
    policy: str
    placed_count: int
    pending_count: int
    inter_node_bandwidth: float
    baseline: Any
    created: datetime.datetime
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        fleet = self.fleet

        clustering: int | None
        clustering = self.clustering

        rosgraph: int | None
        rosgraph = self.rosgraph

        cluster: int | None
        cluster = self.cluster

        policy = self.policy

        placed_count = self.placed_count

        pending_count = self.pending_count

        inter_node_bandwidth = self.inter_node_bandwidth

        baseline = self.baseline

        created = self.created.isoformat()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "fleet": fleet,
                "clustering": clustering,
                "rosgraph": rosgraph,
                "cluster": cluster,
                "policy": policy,
                "placed_count": placed_count,
                "pending_count": pending_count,
                "inter_node_bandwidth": inter_node_bandwidth,
                "baseline": baseline,
                "created": created,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        fleet = d.pop("fleet")

        def _parse_clustering(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        clustering = _parse_clustering(d.pop("clustering"))

        def _parse_rosgraph(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        rosgraph = _parse_rosgraph(d.pop("rosgraph"))

        def _parse_cluster(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        cluster = _parse_cluster(d.pop("cluster"))

        policy = d.pop("policy")

        placed_count = d.pop("placed_count")

        pending_count = d.pop("pending_count")

        inter_node_bandwidth = d.pop("inter_node_bandwidth")

        baseline = d.pop("baseline")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        placement_list = cls(
            id=id,
            fleet=fleet,
            clustering=clustering,
            rosgraph=rosgraph,
            cluster=cluster,
            policy=policy,
            placed_count=placed_count,
            pending_count=pending_count,
            inter_node_bandwidth=inter_node_bandwidth,
            baseline=baseline,
            created=created,
        )

        placement_list.additional_properties = d
        return placement_list

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
