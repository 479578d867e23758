from __future__ import annotations

from collections.abc import Mapping
from io import BytesIO
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from .. import types
from ..types import UNSET, File, Unset

T = TypeVar("T", bound="ThresholdsRequestRequest")


@_attrs_define
class ThresholdsRequestRequest:
    """The base of every plain serializer of the API.

    Attributes:
        file (File): micro-benchmark 2 CSV: fraction, sc_throughput, zc_throughput (GB/s)
        peak_gbps (float | Unset): default: the device's SC peak, else the CSV's largest SC value
    """

    file: File
    peak_gbps: float | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        file = self.file.to_tuple()

        peak_gbps = self.peak_gbps

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "file": file,
            }
        )
        if peak_gbps is not UNSET:
            field_dict["peak_gbps"] = peak_gbps

        return field_dict

    def to_multipart(self) -> types.RequestFiles:
        files: types.RequestFiles = []

        files.append(("file", self.file.to_tuple()))

        if not isinstance(self.peak_gbps, Unset):
            files.append(("peak_gbps", (None, str(self.peak_gbps).encode(), "text/plain")))

        for prop_name, prop in self.additional_properties.items():
            files.append((prop_name, (None, str(prop).encode(), "text/plain")))

        return files

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        file = File(payload=BytesIO(d.pop("file")))

        peak_gbps = d.pop("peak_gbps", UNSET)

        thresholds_request_request = cls(
            file=file,
            peak_gbps=peak_gbps,
        )

        thresholds_request_request.additional_properties = d
        return thresholds_request_request

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
