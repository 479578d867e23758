from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.verdict_enum import VerdictEnum, check_verdict_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="MonitorVerdict")


@_attrs_define
class MonitorVerdict:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        monitor (int):
        verdict (VerdictEnum): * `pending` - no verdict yet
            * `pass` - Pass
            * `fail` - Fail
            * `inconclusive` - Inconclusive
        created (datetime.datetime):
        counters (Any | Unset):
        pending (Any | Unset): start times of the instances still pending
        handler (str | Unset):
    """

    id: int
    monitor: int
    verdict: VerdictEnum
    created: datetime.datetime
    counters: Any | Unset = UNSET
    pending: Any | Unset = UNSET
    handler: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        monitor = self.monitor

        verdict: str = self.verdict

        created = self.created.isoformat()

        counters = self.counters

        pending = self.pending

        handler = self.handler

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "monitor": monitor,
                "verdict": verdict,
                "created": created,
            }
        )
        if counters is not UNSET:
            field_dict["counters"] = counters
        if pending is not UNSET:
            field_dict["pending"] = pending
        if handler is not UNSET:
            field_dict["handler"] = handler

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        monitor = d.pop("monitor")

        verdict = check_verdict_enum(d.pop("verdict"))

        created = datetime.datetime.fromisoformat(d.pop("created"))

        counters = d.pop("counters", UNSET)

        pending = d.pop("pending", UNSET)

        handler = d.pop("handler", UNSET)

        monitor_verdict = cls(
            id=id,
            monitor=monitor,
            verdict=verdict,
            created=created,
            counters=counters,
            pending=pending,
            handler=handler,
        )

        monitor_verdict.additional_properties = d
        return monitor_verdict

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
