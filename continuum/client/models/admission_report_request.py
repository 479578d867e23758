from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="AdmissionReportRequest")


@_attrs_define
class AdmissionReportRequest:
    """What ``python -m continuum.agent admission`` posts.

    Attributes:
        node (str):
        capacity (float): deadline bandwidth, in CPUs
        cluster (int | Unset): default: the fleet's only cluster
        cpus (list[int] | Unset):
        source (str | Unset):
        kernel (str | Unset):
    """

    node: str
    capacity: float
    cluster: int | Unset = UNSET
    cpus: list[int] | Unset = UNSET
    source: str | Unset = UNSET
    kernel: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        node = self.node

        capacity = self.capacity

        cluster = self.cluster

        cpus: list[int] | Unset = UNSET
        if not isinstance(self.cpus, Unset):
            cpus = self.cpus

        source = self.source

        kernel = self.kernel

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "node": node,
                "capacity": capacity,
            }
        )
        if cluster is not UNSET:
            field_dict["cluster"] = cluster
        if cpus is not UNSET:
            field_dict["cpus"] = cpus
        if source is not UNSET:
            field_dict["source"] = source
        if kernel is not UNSET:
            field_dict["kernel"] = kernel

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        node = d.pop("node")

        capacity = d.pop("capacity")

        cluster = d.pop("cluster", UNSET)

        cpus = cast(list[int], d.pop("cpus", UNSET))

        source = d.pop("source", UNSET)

        kernel = d.pop("kernel", UNSET)

        admission_report_request = cls(
            node=node,
            capacity=capacity,
            cluster=cluster,
            cpus=cpus,
            source=source,
            kernel=kernel,
        )

        admission_report_request.additional_properties = d
        return admission_report_request

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
