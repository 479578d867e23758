from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.topic_edit_publisher_rates_hz import TopicEditPublisherRatesHz


T = TypeVar("T", bound="TopicEdit")


@_attrs_define
class TopicEdit:
    """What PATCH (and the ROS graph page's topic rows) may change about one topic: one of the rate forms
    (replaces the rate of every publisher), the message size and type.

        Attributes:
            rate_hz (float | Unset): Hz, 0 to 100,000
            period_ms (float | Unset): ms between messages (instead of rate_hz)
            publisher_rates_hz (TopicEditPublisherRatesHz | Unset): publisher -> Hz
            msg_bytes (float | Unset): bytes, 0 to 1,073,741,824
            msg_type (str | Unset):
    """

    rate_hz: float | Unset = UNSET
    period_ms: float | Unset = UNSET
    publisher_rates_hz: TopicEditPublisherRatesHz | Unset = UNSET
    msg_bytes: float | Unset = UNSET
    msg_type: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        rate_hz = self.rate_hz

        period_ms = self.period_ms

        publisher_rates_hz: dict[str, Any] | Unset = UNSET
        if not isinstance(self.publisher_rates_hz, Unset):
            publisher_rates_hz = self.publisher_rates_hz.to_dict()

        msg_bytes = self.msg_bytes

        msg_type = self.msg_type

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if rate_hz is not UNSET:
            field_dict["rate_hz"] = rate_hz
        if period_ms is not UNSET:
            field_dict["period_ms"] = period_ms
        if publisher_rates_hz is not UNSET:
            field_dict["publisher_rates_hz"] = publisher_rates_hz
        if msg_bytes is not UNSET:
            field_dict["msg_bytes"] = msg_bytes
        if msg_type is not UNSET:
            field_dict["msg_type"] = msg_type

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.topic_edit_publisher_rates_hz import TopicEditPublisherRatesHz

        d = dict(src_dict)
        rate_hz = d.pop("rate_hz", UNSET)

        period_ms = d.pop("period_ms", UNSET)

        _publisher_rates_hz = d.pop("publisher_rates_hz", UNSET)
        publisher_rates_hz: TopicEditPublisherRatesHz | Unset
        if isinstance(_publisher_rates_hz, Unset):
            publisher_rates_hz = UNSET
        else:
            publisher_rates_hz = TopicEditPublisherRatesHz.from_dict(_publisher_rates_hz)

        msg_bytes = d.pop("msg_bytes", UNSET)

        msg_type = d.pop("msg_type", UNSET)

        topic_edit = cls(
            rate_hz=rate_hz,
            period_ms=period_ms,
            publisher_rates_hz=publisher_rates_hz,
            msg_bytes=msg_bytes,
            msg_type=msg_type,
        )

        topic_edit.additional_properties = d
        return topic_edit

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
