from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.algorithm_enum import AlgorithmEnum, check_algorithm_enum
from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.schedule_request_request_params import ScheduleRequestRequestParams


T = TypeVar("T", bound="ScheduleRequestRequest")


@_attrs_define
class ScheduleRequestRequest:
    """Schedule an application on a cluster (its Ready nodes) or on a platform document, for one frame or
    several (``frames``, ``fps`` or ``period``, ``batch``: thesis Eqs. 3.5-3.7).

        Attributes:
            cluster (int | Unset):
            platform (Any | Unset): a continuum.platform/v1 document
            frames (int | Unset): schedule this many frames (pipelined)
            fps (float | Unset): camera rate: frame f released at f/fps
            period (float | Unset): frame period in the DAG's time unit (instead of fps)
            batch (int | Unset): frames buffered and released together
            algorithm (AlgorithmEnum | Unset): * `gfl` - gfl
                * `gfl_c` - gfl_c
                * `heft` - heft
                * `heft4k` - heft4k
                * `visionworks` - visionworks
                * `visionworks_overlap` - visionworks_overlap
                * `xeft` - xeft Default: 'heft'.
            params (ScheduleRequestRequestParams | Unset): algorithm parameters, e.g. rank_mode
    """

    cluster: int | Unset = UNSET
    platform: Any | Unset = UNSET
    frames: int | Unset = UNSET
    fps: float | Unset = UNSET
    period: float | Unset = UNSET
    batch: int | Unset = UNSET
    algorithm: AlgorithmEnum | Unset = "heft"
    params: ScheduleRequestRequestParams | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        cluster = self.cluster

        platform = self.platform

        frames = self.frames

        fps = self.fps

        period = self.period

        batch = self.batch

        algorithm: str | Unset = UNSET
        if not isinstance(self.algorithm, Unset):
            algorithm = self.algorithm

        params: dict[str, Any] | Unset = UNSET
        if not isinstance(self.params, Unset):
            params = self.params.to_dict()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if cluster is not UNSET:
            field_dict["cluster"] = cluster
        if platform is not UNSET:
            field_dict["platform"] = platform
        if frames is not UNSET:
            field_dict["frames"] = frames
        if fps is not UNSET:
            field_dict["fps"] = fps
        if period is not UNSET:
            field_dict["period"] = period
        if batch is not UNSET:
            field_dict["batch"] = batch
        if algorithm is not UNSET:
            field_dict["algorithm"] = algorithm
        if params is not UNSET:
            field_dict["params"] = params

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.schedule_request_request_params import ScheduleRequestRequestParams

        d = dict(src_dict)
        cluster = d.pop("cluster", UNSET)

        platform = d.pop("platform", UNSET)

        frames = d.pop("frames", UNSET)

        fps = d.pop("fps", UNSET)

        period = d.pop("period", UNSET)

        batch = d.pop("batch", UNSET)

        _algorithm = d.pop("algorithm", UNSET)
        algorithm: AlgorithmEnum | Unset
        algorithm = UNSET if isinstance(_algorithm, Unset) else check_algorithm_enum(_algorithm)

        _params = d.pop("params", UNSET)
        params: ScheduleRequestRequestParams | Unset
        params = UNSET if isinstance(_params, Unset) else ScheduleRequestRequestParams.from_dict(_params)

        schedule_request_request = cls(
            cluster=cluster,
            platform=platform,
            frames=frames,
            fps=fps,
            period=period,
            batch=batch,
            algorithm=algorithm,
            params=params,
        )

        schedule_request_request.additional_properties = d
        return schedule_request_request

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
