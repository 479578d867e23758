from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.verdict_enum import VerdictEnum, check_verdict_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="Monitor")


@_attrs_define
class Monitor:
    """``fleet`` defaults to the token's fleet, or to the caller's only fleet.

    Attributes:
        id (int):
        assertion (int):
        cluster (int):
        name (str):
        node_name (str):
        verdict (VerdictEnum): * `pending` - no verdict yet
            * `pass` - Pass
            * `fail` - Fail
            * `inconclusive` - Inconclusive
        events (int):
        violation_count (int):
        active_instances (int):
        cpu (Any): last measured % CPU per node
        created (datetime.datetime):
        updated (datetime.datetime):
        fleet (str | Unset):
        tolerant (bool | Unset): may drop old events and reset under overload (soft properties only, §11.2)
        node (int | None | Unset):
    """

    id: int
    assertion: int
    cluster: int
    name: str
    node_name: str
    verdict: VerdictEnum
    events: int
    violation_count: int
    active_instances: int
    cpu: Any
    created: datetime.datetime
    updated: datetime.datetime
    fleet: str | Unset = UNSET
    tolerant: bool | Unset = UNSET
    node: int | Unset | None = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        assertion = self.assertion

        cluster = self.cluster

        name = self.name

        node_name = self.node_name

        verdict: str = self.verdict

        events = self.events

        violation_count = self.violation_count

        active_instances = self.active_instances

        cpu = self.cpu

        created = self.created.isoformat()

        updated = self.updated.isoformat()

        fleet = self.fleet

        tolerant = self.tolerant

        node: int | Unset | None
        node = UNSET if isinstance(self.node, Unset) else self.node

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "assertion": assertion,
                "cluster": cluster,
                "name": name,
                "node_name": node_name,
                "verdict": verdict,
                "events": events,
                "violation_count": violation_count,
                "active_instances": active_instances,
                "cpu": cpu,
                "created": created,
                "updated": updated,
            }
        )
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if tolerant is not UNSET:
            field_dict["tolerant"] = tolerant
        if node is not UNSET:
            field_dict["node"] = node

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        assertion = d.pop("assertion")

        cluster = d.pop("cluster")

        name = d.pop("name")

        node_name = d.pop("node_name")

        verdict = check_verdict_enum(d.pop("verdict"))

        events = d.pop("events")

        violation_count = d.pop("violation_count")

        active_instances = d.pop("active_instances")

        cpu = d.pop("cpu")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        updated = datetime.datetime.fromisoformat(d.pop("updated"))

        fleet = d.pop("fleet", UNSET)

        tolerant = d.pop("tolerant", UNSET)

        def _parse_node(data: object) -> int | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | Unset | None, data)

        node = _parse_node(d.pop("node", UNSET))

        monitor = cls(
            id=id,
            assertion=assertion,
            cluster=cluster,
            name=name,
            node_name=node_name,
            verdict=verdict,
            events=events,
            violation_count=violation_count,
            active_instances=active_instances,
            cpu=cpu,
            created=created,
            updated=updated,
            fleet=fleet,
            tolerant=tolerant,
            node=node,
        )

        monitor.additional_properties = d
        return monitor

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
