from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.placement_enum import PlacementEnum, check_placement_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="Assignment")


@_attrs_define
class Assignment:
    """The base of every model serializer of the API.

    Attributes:
        task (str):
        processor (str):
        start (float):
        finish (float):
        pod_phase (str): Pending, Running, ..., Deleted
        pod_node (str): the node the pod is bound to
        pod_event (str): the pod's newest event: reason: message
        pod_state_at (datetime.datetime | None): when the watcher last stored a change
        frame (int | Unset):
        core (int | None | Unset): CPU of a multi-core node
        niceness (int | None | Unset):
        placement (PlacementEnum | Unset): * `not_pushed` - Not Pushed
            * `bound` - Bound
            * `failed` - Failed
        placement_message (str | Unset):
        pod_name (str | Unset):
    """

    task: str
    processor: str
    start: float
    finish: float
    pod_phase: str
    pod_node: str
    pod_event: str
    pod_state_at: datetime.datetime | None
    frame: int | Unset = UNSET
    core: int | Unset | None = UNSET
    niceness: int | Unset | None = UNSET
    placement: PlacementEnum | Unset = UNSET
    placement_message: str | Unset = UNSET
    pod_name: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        task = self.task

        processor = self.processor

        start = self.start

        finish = self.finish

        pod_phase = self.pod_phase

        pod_node = self.pod_node

        pod_event = self.pod_event

        pod_state_at: str | None
        if isinstance(self.pod_state_at, datetime.datetime):
            pod_state_at = self.pod_state_at.isoformat()
        else:
            pod_state_at = self.pod_state_at

        frame = self.frame

        core: int | Unset | None
        core = UNSET if isinstance(self.core, Unset) else self.core

        niceness: int | Unset | None
        niceness = UNSET if isinstance(self.niceness, Unset) else self.niceness

        placement: str | Unset = UNSET
        if not isinstance(self.placement, Unset):
            placement = self.placement

        placement_message = self.placement_message

        pod_name = self.pod_name

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "task": task,
                "processor": processor,
                "start": start,
                "finish": finish,
                "pod_phase": pod_phase,
                "pod_node": pod_node,
                "pod_event": pod_event,
                "pod_state_at": pod_state_at,
            }
        )
        if frame is not UNSET:
            field_dict["frame"] = frame
        if core is not UNSET:
            field_dict["core"] = core
        if niceness is not UNSET:
            field_dict["niceness"] = niceness
        if placement is not UNSET:
            field_dict["placement"] = placement
        if placement_message is not UNSET:
            field_dict["placement_message"] = placement_message
        if pod_name is not UNSET:
            field_dict["pod_name"] = pod_name

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        task = d.pop("task")

        processor = d.pop("processor")

        start = d.pop("start")

        finish = d.pop("finish")

        pod_phase = d.pop("pod_phase")

        pod_node = d.pop("pod_node")

        pod_event = d.pop("pod_event")

        def _parse_pod_state_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                pod_state_at_type_0 = datetime.datetime.fromisoformat(data)

                return pod_state_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        pod_state_at = _parse_pod_state_at(d.pop("pod_state_at"))

        frame = d.pop("frame", UNSET)

        def _parse_core(data: object) -> int | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | Unset | None, data)

        core = _parse_core(d.pop("core", UNSET))

        def _parse_niceness(data: object) -> int | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | Unset | None, data)

        niceness = _parse_niceness(d.pop("niceness", UNSET))

        _placement = d.pop("placement", UNSET)
        placement: PlacementEnum | Unset
        placement = UNSET if isinstance(_placement, Unset) else check_placement_enum(_placement)

        placement_message = d.pop("placement_message", UNSET)

        pod_name = d.pop("pod_name", UNSET)

        assignment = cls(
            task=task,
            processor=processor,
            start=start,
            finish=finish,
            pod_phase=pod_phase,
            pod_node=pod_node,
            pod_event=pod_event,
            pod_state_at=pod_state_at,
            frame=frame,
            core=core,
            niceness=niceness,
            placement=placement,
            placement_message=placement_message,
            pod_name=pod_name,
        )

        assignment.additional_properties = d
        return assignment

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
