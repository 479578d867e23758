from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="ClusterDocumentLinkRequest")


@_attrs_define
class ClusterDocumentLinkRequest:
    """The base of every plain serializer of the API.

    Attributes:
        src (str):
        dst (str):
        bandwidth_mbps (float):
        latency_ms (float | Unset):  Default: 0.0.
    """

    src: str
    dst: str
    bandwidth_mbps: float
    latency_ms: float | Unset = 0.0
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        src = self.src

        dst = self.dst

        bandwidth_mbps = self.bandwidth_mbps

        latency_ms = self.latency_ms

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "src": src,
                "dst": dst,
                "bandwidth_mbps": bandwidth_mbps,
            }
        )
        if latency_ms is not UNSET:
            field_dict["latency_ms"] = latency_ms

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        src = d.pop("src")

        dst = d.pop("dst")

        bandwidth_mbps = d.pop("bandwidth_mbps")

        latency_ms = d.pop("latency_ms", UNSET)

        cluster_document_link_request = cls(
            src=src,
            dst=dst,
            bandwidth_mbps=bandwidth_mbps,
            latency_ms=latency_ms,
        )

        cluster_document_link_request.additional_properties = d
        return cluster_document_link_request

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
