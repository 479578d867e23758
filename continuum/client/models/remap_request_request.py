from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="RemapRequestRequest")


@_attrs_define
class RemapRequestRequest:
    """Fail some nodes of a schedule: compute Algorithm 2's remap and, unless ``what_if``, apply it.

    Attributes:
        fail (list[str]): names of the nodes that fail
        what_if (bool | Unset): compute and store only: push nothing Default: False.
        threshold (float | None | Unset): lost HEFT-rank share above which the whole DAG is remapped (default:
            CONTINUUM_REMAP_THRESHOLD)
    """

    fail: list[str]
    what_if: bool | Unset = False
    threshold: float | Unset | None = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        fail = self.fail

        what_if = self.what_if

        threshold: float | Unset | None
        threshold = UNSET if isinstance(self.threshold, Unset) else self.threshold

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "fail": fail,
            }
        )
        if what_if is not UNSET:
            field_dict["what_if"] = what_if
        if threshold is not UNSET:
            field_dict["threshold"] = threshold

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        fail = cast(list[str], d.pop("fail"))

        what_if = d.pop("what_if", UNSET)

        def _parse_threshold(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        threshold = _parse_threshold(d.pop("threshold", UNSET))

        remap_request_request = cls(
            fail=fail,
            what_if=what_if,
            threshold=threshold,
        )

        remap_request_request.additional_properties = d
        return remap_request_request

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
