from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="ImageOptionsRequest")


@_attrs_define
class ImageOptionsRequest:
    """The base of every plain serializer of the API.

    Attributes:
        distro_image (str | Unset):
        ros_distro (str | Unset):
        distro_mib (float | Unset):
        platforms (list[str] | Unset):
        repository (str | Unset):
        tag (str | Unset):
    """

    distro_image: str | Unset = UNSET
    ros_distro: str | Unset = UNSET
    distro_mib: float | Unset = UNSET
    platforms: list[str] | Unset = UNSET
    repository: str | Unset = UNSET
    tag: str | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        distro_image = self.distro_image

        ros_distro = self.ros_distro

        distro_mib = self.distro_mib

        platforms: list[str] | Unset = UNSET
        if not isinstance(self.platforms, Unset):
            platforms = self.platforms

        repository = self.repository

        tag = self.tag

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if distro_image is not UNSET:
            field_dict["distro_image"] = distro_image
        if ros_distro is not UNSET:
            field_dict["ros_distro"] = ros_distro
        if distro_mib is not UNSET:
            field_dict["distro_mib"] = distro_mib
        if platforms is not UNSET:
            field_dict["platforms"] = platforms
        if repository is not UNSET:
            field_dict["repository"] = repository
        if tag is not UNSET:
            field_dict["tag"] = tag

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        distro_image = d.pop("distro_image", UNSET)

        ros_distro = d.pop("ros_distro", UNSET)

        distro_mib = d.pop("distro_mib", UNSET)

        platforms = cast(list[str], d.pop("platforms", UNSET))

        repository = d.pop("repository", UNSET)

        tag = d.pop("tag", UNSET)

        image_options_request = cls(
            distro_image=distro_image,
            ros_distro=ros_distro,
            distro_mib=distro_mib,
            platforms=platforms,
            repository=repository,
            tag=tag,
        )

        image_options_request.additional_properties = d
        return image_options_request

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
