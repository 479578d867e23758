from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="Handler")


@_attrs_define
class Handler:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        cluster (int):
        node (int):
        name (str):
        alive (bool):
        is_coordinator (bool):
        last_seen (datetime.datetime | None):
        free_cpu (float | None):
        verification_cpu (float | None):
        monitor_cpu (Any):
        active (Any): monitors running here
        threshold (float | Unset): % CPU the node may reach with the monitors (MILP capacity)
        delay_ms (float | Unset): topic delay to this node
    """

    id: int
    cluster: int
    node: int
    name: str
    alive: bool
    is_coordinator: bool
    last_seen: datetime.datetime | None
    free_cpu: float | None
    verification_cpu: float | None
    monitor_cpu: Any
    active: Any
    threshold: float | Unset = UNSET
    delay_ms: float | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        node = self.node

        name = self.name

        alive = self.alive

        is_coordinator = self.is_coordinator

        last_seen: str | None
        last_seen = self.last_seen.isoformat() if isinstance(self.last_seen, datetime.datetime) else self.last_seen

        free_cpu: float | None
        free_cpu = self.free_cpu

        verification_cpu: float | None
        verification_cpu = self.verification_cpu

        monitor_cpu = self.monitor_cpu

        active = self.active

        threshold = self.threshold

        delay_ms = self.delay_ms

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "node": node,
                "name": name,
                "alive": alive,
                "is_coordinator": is_coordinator,
                "last_seen": last_seen,
                "free_cpu": free_cpu,
                "verification_cpu": verification_cpu,
                "monitor_cpu": monitor_cpu,
                "active": active,
            }
        )
        if threshold is not UNSET:
            field_dict["threshold"] = threshold
        if delay_ms is not UNSET:
            field_dict["delay_ms"] = delay_ms

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        node = d.pop("node")

        name = d.pop("name")

        alive = d.pop("alive")

        is_coordinator = d.pop("is_coordinator")

        def _parse_last_seen(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                last_seen_type_0 = datetime.datetime.fromisoformat(data)

                return last_seen_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        last_seen = _parse_last_seen(d.pop("last_seen"))

        def _parse_free_cpu(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        free_cpu = _parse_free_cpu(d.pop("free_cpu"))

        def _parse_verification_cpu(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        verification_cpu = _parse_verification_cpu(d.pop("verification_cpu"))

        monitor_cpu = d.pop("monitor_cpu")

        active = d.pop("active")

        threshold = d.pop("threshold", UNSET)

        delay_ms = d.pop("delay_ms", UNSET)

        handler = cls(
            id=id,
            cluster=cluster,
            node=node,
            name=name,
            alive=alive,
            is_coordinator=is_coordinator,
            last_seen=last_seen,
            free_cpu=free_cpu,
            verification_cpu=verification_cpu,
            monitor_cpu=monitor_cpu,
            active=active,
            threshold=threshold,
            delay_ms=delay_ms,
        )

        handler.additional_properties = d
        return handler

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
