from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.blank_enum import BlankEnum, check_blank_enum
from ..models.ros_board_enum import RosBoardEnum, check_ros_board_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="PatchedDeviceProfileRequest")


@_attrs_define
class PatchedDeviceProfileRequest:
    """The base of every model serializer of the API.

    Attributes:
        slug (str | Unset): the device id, e.g. jetson-tx2
        name (str | Unset):
        io_coherent (bool | Unset): hardware I/O coherence: the CPU cache stays on under zero copy (Xavier)
        cpu_threshold_pct (float | Unset): CPU usage (Eq. 3.8) above which the CPU depends on its cache; 100 = never
        gpu_threshold_low_pct (float | Unset): GPU usage (Eq. 3.9) up to which ZC and SC perform alike (zone 1)
        gpu_threshold_high_pct (float | None | Unset): end of zone 2 (a ZC/SC gap under 200 %), when the device has one;
            empty otherwise
        zc_sc_max_speedup (float | None | Unset): largest ZC->SC speedup (micro-benchmark 1)
        zc_sc_max_speedup_verified (bool | Unset):
        sc_zc_max_speedup (float | None | Unset): largest SC->ZC speedup (micro-benchmark 3)
        peak_sc_gbps (float | None | Unset): peak GPU LL->L1 throughput under SC (GB/s), Eq. 3.9
        peak_um_gbps (float | None | Unset): the same under UM
        peak_zc_gbps (float | None | Unset): the same under ZC
        bandwidth_limit_gbps (float | None | Unset):
        ros_board (BlankEnum | RosBoardEnum | Unset): whose ROS transport measurements to quote as the expected overhead

            * `` - none (show both boards' figures)
            * `tx2` - Jetson TX2 (Tables 4.11-4.12)
            * `xavier` - Jetson AGX Xavier (Tables 4.13-4.14)
        notes (str | Unset):
    """

    slug: str | Unset = UNSET
    name: str | Unset = UNSET
    io_coherent: bool | Unset = UNSET
    cpu_threshold_pct: float | Unset = UNSET
    gpu_threshold_low_pct: float | Unset = UNSET
    gpu_threshold_high_pct: float | Unset | None = UNSET
    zc_sc_max_speedup: float | Unset | None = UNSET
    zc_sc_max_speedup_verified: bool | Unset = UNSET
    sc_zc_max_speedup: float | Unset | None = UNSET
    peak_sc_gbps: float | Unset | None = UNSET
    peak_um_gbps: float | Unset | None = UNSET
    peak_zc_gbps: float | Unset | None = UNSET
    bandwidth_limit_gbps: float | Unset | None = UNSET
    ros_board: BlankEnum | RosBoardEnum | Unset = UNSET
    notes: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        slug = self.slug

        name = self.name

        io_coherent = self.io_coherent

        cpu_threshold_pct = self.cpu_threshold_pct

        gpu_threshold_low_pct = self.gpu_threshold_low_pct

        gpu_threshold_high_pct: float | Unset | None
        if isinstance(self.gpu_threshold_high_pct, Unset):
            gpu_threshold_high_pct = UNSET
        else:
            gpu_threshold_high_pct = self.gpu_threshold_high_pct

        zc_sc_max_speedup: float | Unset | None
        zc_sc_max_speedup = UNSET if isinstance(self.zc_sc_max_speedup, Unset) else self.zc_sc_max_speedup

        zc_sc_max_speedup_verified = self.zc_sc_max_speedup_verified

        sc_zc_max_speedup: float | Unset | None
        sc_zc_max_speedup = UNSET if isinstance(self.sc_zc_max_speedup, Unset) else self.sc_zc_max_speedup

        peak_sc_gbps: float | Unset | None
        peak_sc_gbps = UNSET if isinstance(self.peak_sc_gbps, Unset) else self.peak_sc_gbps

        peak_um_gbps: float | Unset | None
        peak_um_gbps = UNSET if isinstance(self.peak_um_gbps, Unset) else self.peak_um_gbps

        peak_zc_gbps: float | Unset | None
        peak_zc_gbps = UNSET if isinstance(self.peak_zc_gbps, Unset) else self.peak_zc_gbps

        bandwidth_limit_gbps: float | Unset | None
        bandwidth_limit_gbps = UNSET if isinstance(self.bandwidth_limit_gbps, Unset) else self.bandwidth_limit_gbps

        ros_board: str | Unset
        if isinstance(self.ros_board, Unset):
            ros_board = UNSET
        elif isinstance(self.ros_board, str):
            ros_board = self.ros_board
        else:
            ros_board = self.ros_board

        notes = self.notes

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if slug is not UNSET:
            field_dict["slug"] = slug
        if name is not UNSET:
            field_dict["name"] = name
        if io_coherent is not UNSET:
            field_dict["io_coherent"] = io_coherent
        if cpu_threshold_pct is not UNSET:
            field_dict["cpu_threshold_pct"] = cpu_threshold_pct
        if gpu_threshold_low_pct is not UNSET:
            field_dict["gpu_threshold_low_pct"] = gpu_threshold_low_pct
        if gpu_threshold_high_pct is not UNSET:
            field_dict["gpu_threshold_high_pct"] = gpu_threshold_high_pct
        if zc_sc_max_speedup is not UNSET:
            field_dict["zc_sc_max_speedup"] = zc_sc_max_speedup
        if zc_sc_max_speedup_verified is not UNSET:
            field_dict["zc_sc_max_speedup_verified"] = zc_sc_max_speedup_verified
        if sc_zc_max_speedup is not UNSET:
            field_dict["sc_zc_max_speedup"] = sc_zc_max_speedup
        if peak_sc_gbps is not UNSET:
            field_dict["peak_sc_gbps"] = peak_sc_gbps
        if peak_um_gbps is not UNSET:
            field_dict["peak_um_gbps"] = peak_um_gbps
        if peak_zc_gbps is not UNSET:
            field_dict["peak_zc_gbps"] = peak_zc_gbps
        if bandwidth_limit_gbps is not UNSET:
            field_dict["bandwidth_limit_gbps"] = bandwidth_limit_gbps
        if ros_board is not UNSET:
            field_dict["ros_board"] = ros_board
        if notes is not UNSET:
            field_dict["notes"] = notes

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        slug = d.pop("slug", UNSET)

        name = d.pop("name", UNSET)

        io_coherent = d.pop("io_coherent", UNSET)

        cpu_threshold_pct = d.pop("cpu_threshold_pct", UNSET)

        gpu_threshold_low_pct = d.pop("gpu_threshold_low_pct", UNSET)

        def _parse_gpu_threshold_high_pct(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        gpu_threshold_high_pct = _parse_gpu_threshold_high_pct(d.pop("gpu_threshold_high_pct", UNSET))

        def _parse_zc_sc_max_speedup(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        zc_sc_max_speedup = _parse_zc_sc_max_speedup(d.pop("zc_sc_max_speedup", UNSET))

        zc_sc_max_speedup_verified = d.pop("zc_sc_max_speedup_verified", UNSET)

        def _parse_sc_zc_max_speedup(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        sc_zc_max_speedup = _parse_sc_zc_max_speedup(d.pop("sc_zc_max_speedup", UNSET))

        def _parse_peak_sc_gbps(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        peak_sc_gbps = _parse_peak_sc_gbps(d.pop("peak_sc_gbps", UNSET))

        def _parse_peak_um_gbps(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        peak_um_gbps = _parse_peak_um_gbps(d.pop("peak_um_gbps", UNSET))

        def _parse_peak_zc_gbps(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        peak_zc_gbps = _parse_peak_zc_gbps(d.pop("peak_zc_gbps", UNSET))

        def _parse_bandwidth_limit_gbps(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        bandwidth_limit_gbps = _parse_bandwidth_limit_gbps(d.pop("bandwidth_limit_gbps", UNSET))

        def _parse_ros_board(data: object) -> BlankEnum | RosBoardEnum | Unset:
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                ros_board_type_0 = check_ros_board_enum(data)

                return ros_board_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            if not isinstance(data, str):
                raise TypeError()
            ros_board_type_1 = check_blank_enum(data)

            return ros_board_type_1

        ros_board = _parse_ros_board(d.pop("ros_board", UNSET))

        notes = d.pop("notes", UNSET)

        patched_device_profile_request = cls(
            slug=slug,
            name=name,
            io_coherent=io_coherent,
            cpu_threshold_pct=cpu_threshold_pct,
            gpu_threshold_low_pct=gpu_threshold_low_pct,
            gpu_threshold_high_pct=gpu_threshold_high_pct,
            zc_sc_max_speedup=zc_sc_max_speedup,
            zc_sc_max_speedup_verified=zc_sc_max_speedup_verified,
            sc_zc_max_speedup=sc_zc_max_speedup,
            peak_sc_gbps=peak_sc_gbps,
            peak_um_gbps=peak_um_gbps,
            peak_zc_gbps=peak_zc_gbps,
            bandwidth_limit_gbps=bandwidth_limit_gbps,
            ros_board=ros_board,
            notes=notes,
        )

        patched_device_profile_request.additional_properties = d
        return patched_device_profile_request

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
