from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="Violation")


@_attrs_define
class Violation:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        monitor (int):
        monitor_name (str):
        assertion (int):
        time_ms (float):
        instance_start_ms (float):
        created (datetime.datetime):
        event (Any | Unset): [variable, value, timestamp] of the deciding event
        handler (str | Unset): node whose handler found it, or in-process
    """

    id: int
    monitor: int
    monitor_name: str
    assertion: int
    time_ms: float
    instance_start_ms: float
    created: datetime.datetime
    event: Any | Unset = UNSET
    handler: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        monitor = self.monitor

        monitor_name = self.monitor_name

        assertion = self.assertion

        time_ms = self.time_ms

        instance_start_ms = self.instance_start_ms

        created = self.created.isoformat()

        event = self.event

        handler = self.handler

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "monitor": monitor,
                "monitor_name": monitor_name,
                "assertion": assertion,
                "time_ms": time_ms,
                "instance_start_ms": instance_start_ms,
                "created": created,
            }
        )
        if event is not UNSET:
            field_dict["event"] = event
        if handler is not UNSET:
            field_dict["handler"] = handler

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        monitor = d.pop("monitor")

        monitor_name = d.pop("monitor_name")

        assertion = d.pop("assertion")

        time_ms = d.pop("time_ms")

        instance_start_ms = d.pop("instance_start_ms")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        event = d.pop("event", UNSET)

        handler = d.pop("handler", UNSET)

        violation = cls(
            id=id,
            monitor=monitor,
            monitor_name=monitor_name,
            assertion=assertion,
            time_ms=time_ms,
            instance_start_ms=instance_start_ms,
            created=created,
            event=event,
            handler=handler,
        )

        violation.additional_properties = d
        return violation

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
