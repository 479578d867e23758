from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

T = TypeVar("T", bound="Monitoring")


@_attrs_define
class Monitoring:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        cluster (int):
        name (str): metadata.name (default <pod>-<container>)
        node (str):
        container_name (str):
        pod (str):
        missed_period (int):
        missed_total (int):
        received_at (datetime.datetime):
        kube_synced (bool): the custom object shows these counters
    """

    id: int
    cluster: int
    name: str
    node: str
    container_name: str
    pod: str
    missed_period: int
    missed_total: int
    received_at: datetime.datetime
    kube_synced: bool
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        name = self.name

        node = self.node

        container_name = self.container_name

        pod = self.pod

        missed_period = self.missed_period

        missed_total = self.missed_total

        received_at = self.received_at.isoformat()

        kube_synced = self.kube_synced

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "name": name,
                "node": node,
                "container_name": container_name,
                "pod": pod,
                "missed_period": missed_period,
                "missed_total": missed_total,
                "received_at": received_at,
                "kube_synced": kube_synced,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        name = d.pop("name")

        node = d.pop("node")

        container_name = d.pop("container_name")

        pod = d.pop("pod")

        missed_period = d.pop("missed_period")

        missed_total = d.pop("missed_total")

        received_at = datetime.datetime.fromisoformat(d.pop("received_at"))

        kube_synced = d.pop("kube_synced")

        monitoring = cls(
            id=id,
            cluster=cluster,
            name=name,
            node=node,
            container_name=container_name,
            pod=pod,
            missed_period=missed_period,
            missed_total=missed_total,
            received_at=received_at,
            kube_synced=kube_synced,
        )

        monitoring.additional_properties = d
        return monitoring

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
