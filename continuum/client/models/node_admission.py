from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

T = TypeVar("T", bound="NodeAdmission")


@_attrs_define
class NodeAdmission:
    """A node's admissible RT bandwidth: the cluster file's, its kernel's, and which one RT-Kube's filter uses.

    Attributes:
        id (int):
        cluster (int):
        name (str):
        cpu (float): CPU cores
        rt (bool): real-time capable
        rt_threshold (float | None): admissible RT utilization (M x 0.95)
        kernel_rt_capacity (float | None): deadline bandwidth its kernel admits
        kernel_rt_source (str): how the node read it
        kernel_reported_at (datetime.datetime | None):
        rt_capacity (float): what RT-Kube's filter admits up to
        rt_capacity_source (str):
    """

    id: int
    cluster: int
    name: str
    cpu: float
    rt: bool
    rt_threshold: float | None
    kernel_rt_capacity: float | None
    kernel_rt_source: str
    kernel_reported_at: datetime.datetime | None
    rt_capacity: float
    rt_capacity_source: str
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        name = self.name

        cpu = self.cpu

        rt = self.rt

        rt_threshold: float | None
        rt_threshold = self.rt_threshold

        kernel_rt_capacity: float | None
        kernel_rt_capacity = self.kernel_rt_capacity

        kernel_rt_source = self.kernel_rt_source

        kernel_reported_at: str | None
        if isinstance(self.kernel_reported_at, datetime.datetime):
            kernel_reported_at = self.kernel_reported_at.isoformat()
        else:
            kernel_reported_at = self.kernel_reported_at

        rt_capacity = self.rt_capacity

        rt_capacity_source = self.rt_capacity_source

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "name": name,
                "cpu": cpu,
                "rt": rt,
                "rt_threshold": rt_threshold,
                "kernel_rt_capacity": kernel_rt_capacity,
                "kernel_rt_source": kernel_rt_source,
                "kernel_reported_at": kernel_reported_at,
                "rt_capacity": rt_capacity,
                "rt_capacity_source": rt_capacity_source,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        name = d.pop("name")

        cpu = d.pop("cpu")

        rt = d.pop("rt")

        def _parse_rt_threshold(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        rt_threshold = _parse_rt_threshold(d.pop("rt_threshold"))

        def _parse_kernel_rt_capacity(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        kernel_rt_capacity = _parse_kernel_rt_capacity(d.pop("kernel_rt_capacity"))

        kernel_rt_source = d.pop("kernel_rt_source")

        def _parse_kernel_reported_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                kernel_reported_at_type_0 = datetime.datetime.fromisoformat(data)

                return kernel_reported_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        kernel_reported_at = _parse_kernel_reported_at(d.pop("kernel_reported_at"))

        rt_capacity = d.pop("rt_capacity")

        rt_capacity_source = d.pop("rt_capacity_source")

        node_admission = cls(
            id=id,
            cluster=cluster,
            name=name,
            cpu=cpu,
            rt=rt,
            rt_threshold=rt_threshold,
            kernel_rt_capacity=kernel_rt_capacity,
            kernel_rt_source=kernel_rt_source,
            kernel_reported_at=kernel_reported_at,
            rt_capacity=rt_capacity,
            rt_capacity_source=rt_capacity_source,
        )

        node_admission.additional_properties = d
        return node_admission

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
