from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="MigrationEvent")


@_attrs_define
class MigrationEvent:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        run (int):
        monitor_name (str):
        source (str):
        target (str):
        created (datetime.datetime):
        monitor (int | None | Unset):
        t (float | None | Unset): seconds into the series (simulations)
        events_moved (int | None | Unset):
    """

    id: int
    run: int
    monitor_name: str
    source: str
    target: str
    created: datetime.datetime
    monitor: int | Unset | None = UNSET
    t: float | Unset | None = UNSET
    events_moved: int | Unset | None = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        run = self.run

        monitor_name = self.monitor_name

        source = self.source

        target = self.target

        created = self.created.isoformat()

        monitor: int | Unset | None
        monitor = UNSET if isinstance(self.monitor, Unset) else self.monitor

        t: float | Unset | None
        t = UNSET if isinstance(self.t, Unset) else self.t

        events_moved: int | Unset | None
        events_moved = UNSET if isinstance(self.events_moved, Unset) else self.events_moved

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "run": run,
                "monitor_name": monitor_name,
                "source": source,
                "target": target,
                "created": created,
            }
        )
        if monitor is not UNSET:
            field_dict["monitor"] = monitor
        if t is not UNSET:
            field_dict["t"] = t
        if events_moved is not UNSET:
            field_dict["events_moved"] = events_moved

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        run = d.pop("run")

        monitor_name = d.pop("monitor_name")

        source = d.pop("source")

        target = d.pop("target")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        def _parse_monitor(data: object) -> int | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | Unset | None, data)

        monitor = _parse_monitor(d.pop("monitor", UNSET))

        def _parse_t(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        t = _parse_t(d.pop("t", UNSET))

        def _parse_events_moved(data: object) -> int | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | Unset | None, data)

        events_moved = _parse_events_moved(d.pop("events_moved", UNSET))

        migration_event = cls(
            id=id,
            run=run,
            monitor_name=monitor_name,
            source=source,
            target=target,
            created=created,
            monitor=monitor,
            t=t,
            events_moved=events_moved,
        )

        migration_event.additional_properties = d
        return migration_event

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
