from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="AllocationRequestRequest")


@_attrs_define
class AllocationRequestRequest:
    """Start the MILP on a cluster's statistics (``cluster``) or on a ``stats`` document.

    Attributes:
        cluster (int | Unset):
        stats (Any | Unset):
        apply (bool | Unset): move the monitors (cluster only) Default: False.
        work_limit (int | Unset): branch-and-bound nodes per solve: the same input gives the same allocation under any
            load Default: 2000.
        time_limit (float | Unset): optional wall-clock cap in seconds (the allocation may then depend on the machine's
            load)
    """

    cluster: int | Unset = UNSET
    stats: Any | Unset = UNSET
    apply: bool | Unset = False
    work_limit: int | Unset = 2000
    time_limit: float | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        cluster = self.cluster

        stats = self.stats

        apply = self.apply

        work_limit = self.work_limit

        time_limit = self.time_limit

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if cluster is not UNSET:
            field_dict["cluster"] = cluster
        if stats is not UNSET:
            field_dict["stats"] = stats
        if apply is not UNSET:
            field_dict["apply"] = apply
        if work_limit is not UNSET:
            field_dict["work_limit"] = work_limit
        if time_limit is not UNSET:
            field_dict["time_limit"] = time_limit

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        cluster = d.pop("cluster", UNSET)

        stats = d.pop("stats", UNSET)

        apply = d.pop("apply", UNSET)

        work_limit = d.pop("work_limit", UNSET)

        time_limit = d.pop("time_limit", UNSET)

        allocation_request_request = cls(
            cluster=cluster,
            stats=stats,
            apply=apply,
            work_limit=work_limit,
            time_limit=time_limit,
        )

        allocation_request_request.additional_properties = d
        return allocation_request_request

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
