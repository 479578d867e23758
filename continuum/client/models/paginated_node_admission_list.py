from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.node_admission import NodeAdmission


T = TypeVar("T", bound="PaginatedNodeAdmissionList")


@_attrs_define
class PaginatedNodeAdmissionList:
    """
    Attributes:
        count (int):  Example: 123.
        results (list[NodeAdmission]):
        next_ (None | str | Unset):  Example: http://api.example.org/accounts/?offset=400&limit=100.
        previous (None | str | Unset):  Example: http://api.example.org/accounts/?offset=200&limit=100.
    """

    count: int
    results: list[NodeAdmission]
    next_: str | Unset | None = UNSET
    previous: str | Unset | None = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        count = self.count

        results = []
        for results_item_data in self.results:
            results_item = results_item_data.to_dict()
            results.append(results_item)

        next_: str | Unset | None
        next_ = UNSET if isinstance(self.next_, Unset) else self.next_

        previous: str | Unset | None
        previous = UNSET if isinstance(self.previous, Unset) else self.previous

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "count": count,
                "results": results,
            }
        )
        if next_ is not UNSET:
            field_dict["next"] = next_
        if previous is not UNSET:
            field_dict["previous"] = previous

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.node_admission import NodeAdmission

        d = dict(src_dict)
        count = d.pop("count")

        results = []
        _results = d.pop("results")
        for results_item_data in _results:
            results_item = NodeAdmission.from_dict(results_item_data)

            results.append(results_item)

        def _parse_next_(data: object) -> str | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(str | Unset | None, data)

        next_ = _parse_next_(d.pop("next", UNSET))

        def _parse_previous(data: object) -> str | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(str | Unset | None, data)

        previous = _parse_previous(d.pop("previous", UNSET))

        paginated_node_admission_list = cls(
            count=count,
            results=results,
            next_=next_,
            previous=previous,
        )

        paginated_node_admission_list.additional_properties = d
        return paginated_node_admission_list

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
