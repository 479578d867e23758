from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.what_if_request_params import WhatIfRequestParams


T = TypeVar("T", bound="WhatIfRequest")


@_attrs_define
class WhatIfRequest:
    """The base of every plain serializer of the API.

    Attributes:
        cluster (int):
        realtimes (list[int] | Unset): RealTime ids (default: all of the cluster)
        containers (Any | Unset): a continuum.rtset/v1 document
        params (WhatIfRequestParams | Unset): k, b_score_argument, sort_tiebreak
        with_bound (bool | Unset): start from the pods bound now Default: True.
    """

    cluster: int
    realtimes: list[int] | Unset = UNSET
    containers: Any | Unset = UNSET
    params: WhatIfRequestParams | Unset = UNSET
    with_bound: bool | Unset = True
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        cluster = self.cluster

        realtimes: list[int] | Unset = UNSET
        if not isinstance(self.realtimes, Unset):
            realtimes = self.realtimes

        containers = self.containers

        params: dict[str, Any] | Unset = UNSET
        if not isinstance(self.params, Unset):
            params = self.params.to_dict()

        with_bound = self.with_bound

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "cluster": cluster,
            }
        )
        if realtimes is not UNSET:
            field_dict["realtimes"] = realtimes
        if containers is not UNSET:
            field_dict["containers"] = containers
        if params is not UNSET:
            field_dict["params"] = params
        if with_bound is not UNSET:
            field_dict["with_bound"] = with_bound

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.what_if_request_params import WhatIfRequestParams

        d = dict(src_dict)
        cluster = d.pop("cluster")

        realtimes = cast(list[int], d.pop("realtimes", UNSET))

        containers = d.pop("containers", UNSET)

        _params = d.pop("params", UNSET)
        params: WhatIfRequestParams | Unset
        params = UNSET if isinstance(_params, Unset) else WhatIfRequestParams.from_dict(_params)

        with_bound = d.pop("with_bound", UNSET)

        what_if_request = cls(
            cluster=cluster,
            realtimes=realtimes,
            containers=containers,
            params=params,
            with_bound=with_bound,
        )

        what_if_request.additional_properties = d
        return what_if_request

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
