from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.blank_enum import BlankEnum, check_blank_enum
from ..models.pin_enum import PinEnum, check_pin_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="RosNodeEditRequest")


@_attrs_define
class RosNodeEditRequest:
    """What PATCH (and the ROS graph page's node rows) may change about one ROS node. ``null`` level: the level
    proposed from the graph's structure; ``null`` pin: the level decides (drivers stay on the robot).

        Attributes:
            level (None | str | Unset): Fig. 3.19 level: mission, macro, functionality, driver (null: proposed from the
                structure)
            context (str | Unset):
            origin (str | Unset):
            cpu (float | None | Unset): cores, 0 to 1,024
            memory_mib (float | None | Unset): MiB, 0 to 1,048,576
            packages (list[str] | Unset):
            pin (BlankEnum | None | PinEnum | Unset): robot: keep on the robot's boards; free: the placement may move it;
                null: drivers stay on the robot

                * `robot` - robot
                * `free` - free
    """

    level: str | Unset | None = UNSET
    context: str | Unset = UNSET
    origin: str | Unset = UNSET
    cpu: float | Unset | None = UNSET
    memory_mib: float | Unset | None = UNSET
    packages: list[str] | Unset = UNSET
    pin: BlankEnum | PinEnum | Unset | None = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        level: str | Unset | None
        level = UNSET if isinstance(self.level, Unset) else self.level

        context = self.context

        origin = self.origin

        cpu: float | Unset | None
        cpu = UNSET if isinstance(self.cpu, Unset) else self.cpu

        memory_mib: float | Unset | None
        memory_mib = UNSET if isinstance(self.memory_mib, Unset) else self.memory_mib

        packages: list[str] | Unset = UNSET
        if not isinstance(self.packages, Unset):
            packages = self.packages

        pin: str | Unset | None
        if isinstance(self.pin, Unset):
            pin = UNSET
        elif isinstance(self.pin, (str, str)):
            pin = self.pin
        else:
            pin = self.pin

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if level is not UNSET:
            field_dict["level"] = level
        if context is not UNSET:
            field_dict["context"] = context
        if origin is not UNSET:
            field_dict["origin"] = origin
        if cpu is not UNSET:
            field_dict["cpu"] = cpu
        if memory_mib is not UNSET:
            field_dict["memory_mib"] = memory_mib
        if packages is not UNSET:
            field_dict["packages"] = packages
        if pin is not UNSET:
            field_dict["pin"] = pin

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)

        def _parse_level(data: object) -> str | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(str | Unset | None, data)

        level = _parse_level(d.pop("level", UNSET))

        context = d.pop("context", UNSET)

        origin = d.pop("origin", UNSET)

        def _parse_cpu(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        cpu = _parse_cpu(d.pop("cpu", UNSET))

        def _parse_memory_mib(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        memory_mib = _parse_memory_mib(d.pop("memory_mib", UNSET))

        packages = cast(list[str], d.pop("packages", UNSET))

        def _parse_pin(data: object) -> BlankEnum | PinEnum | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                pin_type_0 = check_pin_enum(data)

                return pin_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            try:
                if not isinstance(data, str):
                    raise TypeError()
                pin_type_1 = check_blank_enum(data)

                return pin_type_1
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(BlankEnum | PinEnum | Unset | None, data)

        pin = _parse_pin(d.pop("pin", UNSET))

        ros_node_edit_request = cls(
            level=level,
            context=context,
            origin=origin,
            cpu=cpu,
            memory_mib=memory_mib,
            packages=packages,
            pin=pin,
        )

        ros_node_edit_request.additional_properties = d
        return ros_node_edit_request

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
