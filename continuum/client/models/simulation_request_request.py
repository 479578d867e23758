from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.scenario_enum import ScenarioEnum, check_scenario_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="SimulationRequestRequest")


@_attrs_define
class SimulationRequestRequest:
    """The base of every plain serializer of the API.

    Attributes:
        scenario (ScenarioEnum | Unset): * `kairos` - kairos
            * `synthetic` - synthetic Default: 'kairos'.
        duration_s (float | Unset):
        time_limit (float | Unset):
    """

    scenario: ScenarioEnum | Unset = "kairos"
    duration_s: float | Unset = UNSET
    time_limit: float | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        scenario: str | Unset = UNSET
        if not isinstance(self.scenario, Unset):
            scenario = self.scenario

        duration_s = self.duration_s

        time_limit = self.time_limit

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if scenario is not UNSET:
            field_dict["scenario"] = scenario
        if duration_s is not UNSET:
            field_dict["duration_s"] = duration_s
        if time_limit is not UNSET:
            field_dict["time_limit"] = time_limit

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        _scenario = d.pop("scenario", UNSET)
        scenario: ScenarioEnum | Unset
        scenario = UNSET if isinstance(_scenario, Unset) else check_scenario_enum(_scenario)

        duration_s = d.pop("duration_s", UNSET)

        time_limit = d.pop("time_limit", UNSET)

        simulation_request_request = cls(
            scenario=scenario,
            duration_s=duration_s,
            time_limit=time_limit,
        )

        simulation_request_request.additional_properties = d
        return simulation_request_request

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
