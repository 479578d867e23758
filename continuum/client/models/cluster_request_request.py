from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.mode_enum import ModeEnum, check_mode_enum
from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.image_options_request import ImageOptionsRequest


T = TypeVar("T", bound="ClusterRequestRequest")


@_attrs_define
class ClusterRequestRequest:
    """Cluster the graph's ROS nodes into N containers (Listing 3.20), or as many as Eq. 3.13 allows.

    Attributes:
        containers (int | Unset): number of containers N
        memory_mib (float | Unset): memory for containers (Eq. 3.13)
        overhead_mib (float | Unset): memory cost of one container
        mode (ModeEnum | Unset): * `per_topic` - per_topic
            * `literal` - literal Default: 'per_topic'.
        max_cluster_share (float | None | Unset):
        max_cluster_memory_mib (float | None | Unset):
        images (ImageOptionsRequest | Unset): The base of every plain serializer of the API.
    """

    containers: int | Unset = UNSET
    memory_mib: float | Unset = UNSET
    overhead_mib: float | Unset = UNSET
    mode: ModeEnum | Unset = "per_topic"
    max_cluster_share: float | Unset | None = UNSET
    max_cluster_memory_mib: float | Unset | None = UNSET
    images: ImageOptionsRequest | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        containers = self.containers

        memory_mib = self.memory_mib

        overhead_mib = self.overhead_mib

        mode: str | Unset = UNSET
        if not isinstance(self.mode, Unset):
            mode = self.mode

        max_cluster_share: float | Unset | None
        max_cluster_share = UNSET if isinstance(self.max_cluster_share, Unset) else self.max_cluster_share

        max_cluster_memory_mib: float | Unset | None
        if isinstance(self.max_cluster_memory_mib, Unset):
            max_cluster_memory_mib = UNSET
        else:
            max_cluster_memory_mib = self.max_cluster_memory_mib

        images: dict[str, Any] | Unset = UNSET
        if not isinstance(self.images, Unset):
            images = self.images.to_dict()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if containers is not UNSET:
            field_dict["containers"] = containers
        if memory_mib is not UNSET:
            field_dict["memory_mib"] = memory_mib
        if overhead_mib is not UNSET:
            field_dict["overhead_mib"] = overhead_mib
        if mode is not UNSET:
            field_dict["mode"] = mode
        if max_cluster_share is not UNSET:
            field_dict["max_cluster_share"] = max_cluster_share
        if max_cluster_memory_mib is not UNSET:
            field_dict["max_cluster_memory_mib"] = max_cluster_memory_mib
        if images is not UNSET:
            field_dict["images"] = images

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.image_options_request import ImageOptionsRequest

        d = dict(src_dict)
        containers = d.pop("containers", UNSET)

        memory_mib = d.pop("memory_mib", UNSET)

        overhead_mib = d.pop("overhead_mib", UNSET)

        _mode = d.pop("mode", UNSET)
        mode: ModeEnum | Unset
        mode = UNSET if isinstance(_mode, Unset) else check_mode_enum(_mode)

        def _parse_max_cluster_share(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        max_cluster_share = _parse_max_cluster_share(d.pop("max_cluster_share", UNSET))

        def _parse_max_cluster_memory_mib(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        max_cluster_memory_mib = _parse_max_cluster_memory_mib(d.pop("max_cluster_memory_mib", UNSET))

        _images = d.pop("images", UNSET)
        images: ImageOptionsRequest | Unset
        images = UNSET if isinstance(_images, Unset) else ImageOptionsRequest.from_dict(_images)

        cluster_request_request = cls(
            containers=containers,
            memory_mib=memory_mib,
            overhead_mib=overhead_mib,
            mode=mode,
            max_cluster_share=max_cluster_share,
            max_cluster_memory_mib=max_cluster_memory_mib,
            images=images,
        )

        cluster_request_request.additional_properties = d
        return cluster_request_request

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
