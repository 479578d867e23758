from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.algorithm_enum import AlgorithmEnum, check_algorithm_enum
from ..models.comm_mode_enum import CommModeEnum, check_comm_mode_enum
from ..models.rank_mode_enum import RankModeEnum, check_rank_mode_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="CompareRequestRequest")


@_attrs_define
class CompareRequestRequest:
    """Run several algorithms on one application and target and compare them (thesis Tables 4.1, 4.3).

    Attributes:
        cluster (int | Unset):
        platform (Any | Unset): a continuum.platform/v1 document
        frames (int | Unset): schedule this many frames (pipelined)
        fps (float | Unset): camera rate: frame f released at f/fps
        period (float | Unset): frame period in the DAG's time unit (instead of fps)
        batch (int | Unset): frames buffered and released together
        algorithms (list[AlgorithmEnum] | Unset):
        rank_mode (RankModeEnum | Unset): * `mean` - mean
            * `max` - max Default: 'max'.
        comm_mode (CommModeEnum | Unset): * `pairs` - pairs
            * `impl` - impl Default: 'impl'.
    """

    cluster: int | Unset = UNSET
    platform: Any | Unset = UNSET
    frames: int | Unset = UNSET
    fps: float | Unset = UNSET
    period: float | Unset = UNSET
    batch: int | Unset = UNSET
    algorithms: list[AlgorithmEnum] | Unset = UNSET
    rank_mode: RankModeEnum | Unset = "max"
    comm_mode: CommModeEnum | Unset = "impl"
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        cluster = self.cluster

        platform = self.platform

        frames = self.frames

        fps = self.fps

        period = self.period

        batch = self.batch

        algorithms: list[str] | Unset = UNSET
        if not isinstance(self.algorithms, Unset):
            algorithms = []
            for algorithms_item_data in self.algorithms:
                algorithms_item: str = algorithms_item_data
                algorithms.append(algorithms_item)

        rank_mode: str | Unset = UNSET
        if not isinstance(self.rank_mode, Unset):
            rank_mode = self.rank_mode

        comm_mode: str | Unset = UNSET
        if not isinstance(self.comm_mode, Unset):
            comm_mode = self.comm_mode

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
        if algorithms is not UNSET:
            field_dict["algorithms"] = algorithms
        if rank_mode is not UNSET:
            field_dict["rank_mode"] = rank_mode
        if comm_mode is not UNSET:
            field_dict["comm_mode"] = comm_mode

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        cluster = d.pop("cluster", UNSET)

        platform = d.pop("platform", UNSET)

        frames = d.pop("frames", UNSET)

        fps = d.pop("fps", UNSET)

        period = d.pop("period", UNSET)

        batch = d.pop("batch", UNSET)

        _algorithms = d.pop("algorithms", UNSET)
        algorithms: list[AlgorithmEnum] | Unset = UNSET
        if _algorithms is not UNSET:
            algorithms = []
            for algorithms_item_data in _algorithms:
                algorithms_item = check_algorithm_enum(algorithms_item_data)

                algorithms.append(algorithms_item)

        _rank_mode = d.pop("rank_mode", UNSET)
        rank_mode: RankModeEnum | Unset
        rank_mode = UNSET if isinstance(_rank_mode, Unset) else check_rank_mode_enum(_rank_mode)

        _comm_mode = d.pop("comm_mode", UNSET)
        comm_mode: CommModeEnum | Unset
        comm_mode = UNSET if isinstance(_comm_mode, Unset) else check_comm_mode_enum(_comm_mode)

        compare_request_request = cls(
            cluster=cluster,
            platform=platform,
            frames=frames,
            fps=fps,
            period=period,
            batch=batch,
            algorithms=algorithms,
            rank_mode=rank_mode,
            comm_mode=comm_mode,
        )

        compare_request_request.additional_properties = d
        return compare_request_request

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
