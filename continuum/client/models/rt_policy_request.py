from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.b_score_argument_enum import BScoreArgumentEnum, check_b_score_argument_enum
from ..models.eviction_policy_enum import EvictionPolicyEnum, check_eviction_policy_enum
from ..models.linear_resource_enum import LinearResourceEnum, check_linear_resource_enum
from ..models.sort_tiebreak_enum import SortTiebreakEnum, check_sort_tiebreak_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="RTPolicyRequest")


@_attrs_define
class RTPolicyRequest:
    """The base of every model serializer of the API.

    Attributes:
        cluster (int):
        threshold_period (int | None | Unset): evict when a report's missed deadlines in the period exceed this
        threshold_total (int | None | Unset): evict when the missed deadlines in total exceed this (empty: off)
        update_frequency_hz (float | Unset):
        eviction_policy (EvictionPolicyEnum | Unset): * `linear` - linear (one resource, O(n))
            * `linearithmic` - linearithmic (two resources, O(n log n))
            * `quadratic` - quadratic (communication, O(n²))
        linear_resource (LinearResourceEnum | Unset): * `cpu` - cpu
            * `memory` - memory
        taint_duration_s (float | Unset): how long a violating node stays tainted
        cooldown_s (float | None | Unset): empty: the taint duration
        recreate_orphans (bool | Unset): recreate an evicted pod that no controller owns (a Deployment's ReplicaSet
            recreates its own)
        traffic (Any | Unset): quadratic policy: traffic between containers, {"a|b": bytes/s}
        k (float | Unset): Eq. 3.18's K
        b_score_argument (BScoreArgumentEnum | Unset): * `free` - free capacity (Eq. 3.18)
            * `load` - load (prose)
        sort_tiebreak (SortTiebreakEnum | Unset): * `arrival` - arrival
            * `utilization` - utilization
    """

    cluster: int
    threshold_period: int | Unset | None = UNSET
    threshold_total: int | Unset | None = UNSET
    update_frequency_hz: float | Unset = UNSET
    eviction_policy: EvictionPolicyEnum | Unset = UNSET
    linear_resource: LinearResourceEnum | Unset = UNSET
    taint_duration_s: float | Unset = UNSET
    cooldown_s: float | Unset | None = UNSET
    recreate_orphans: bool | Unset = UNSET
    traffic: Any | Unset = UNSET
    k: float | Unset = UNSET
    b_score_argument: BScoreArgumentEnum | Unset = UNSET
    sort_tiebreak: SortTiebreakEnum | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        cluster = self.cluster

        threshold_period: int | Unset | None
        threshold_period = UNSET if isinstance(self.threshold_period, Unset) else self.threshold_period

        threshold_total: int | Unset | None
        threshold_total = UNSET if isinstance(self.threshold_total, Unset) else self.threshold_total

        update_frequency_hz = self.update_frequency_hz

        eviction_policy: str | Unset = UNSET
        if not isinstance(self.eviction_policy, Unset):
            eviction_policy = self.eviction_policy

        linear_resource: str | Unset = UNSET
        if not isinstance(self.linear_resource, Unset):
            linear_resource = self.linear_resource

        taint_duration_s = self.taint_duration_s

        cooldown_s: float | Unset | None
        cooldown_s = UNSET if isinstance(self.cooldown_s, Unset) else self.cooldown_s

        recreate_orphans = self.recreate_orphans

        traffic = self.traffic

        k = self.k

        b_score_argument: str | Unset = UNSET
        if not isinstance(self.b_score_argument, Unset):
            b_score_argument = self.b_score_argument

        sort_tiebreak: str | Unset = UNSET
        if not isinstance(self.sort_tiebreak, Unset):
            sort_tiebreak = self.sort_tiebreak

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "cluster": cluster,
            }
        )
        if threshold_period is not UNSET:
            field_dict["threshold_period"] = threshold_period
        if threshold_total is not UNSET:
            field_dict["threshold_total"] = threshold_total
        if update_frequency_hz is not UNSET:
            field_dict["update_frequency_hz"] = update_frequency_hz
        if eviction_policy is not UNSET:
            field_dict["eviction_policy"] = eviction_policy
        if linear_resource is not UNSET:
            field_dict["linear_resource"] = linear_resource
        if taint_duration_s is not UNSET:
            field_dict["taint_duration_s"] = taint_duration_s
        if cooldown_s is not UNSET:
            field_dict["cooldown_s"] = cooldown_s
        if recreate_orphans is not UNSET:
            field_dict["recreate_orphans"] = recreate_orphans
        if traffic is not UNSET:
            field_dict["traffic"] = traffic
        if k is not UNSET:
            field_dict["k"] = k
        if b_score_argument is not UNSET:
            field_dict["b_score_argument"] = b_score_argument
        if sort_tiebreak is not UNSET:
            field_dict["sort_tiebreak"] = sort_tiebreak

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        cluster = d.pop("cluster")

        def _parse_threshold_period(data: object) -> int | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | Unset | None, data)

        threshold_period = _parse_threshold_period(d.pop("threshold_period", UNSET))

        def _parse_threshold_total(data: object) -> int | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(int | Unset | None, data)

        threshold_total = _parse_threshold_total(d.pop("threshold_total", UNSET))

        update_frequency_hz = d.pop("update_frequency_hz", UNSET)

        _eviction_policy = d.pop("eviction_policy", UNSET)
        eviction_policy: EvictionPolicyEnum | Unset
        eviction_policy = UNSET if isinstance(_eviction_policy, Unset) else check_eviction_policy_enum(_eviction_policy)

        _linear_resource = d.pop("linear_resource", UNSET)
        linear_resource: LinearResourceEnum | Unset
        linear_resource = UNSET if isinstance(_linear_resource, Unset) else check_linear_resource_enum(_linear_resource)

        taint_duration_s = d.pop("taint_duration_s", UNSET)

        def _parse_cooldown_s(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        cooldown_s = _parse_cooldown_s(d.pop("cooldown_s", UNSET))

        recreate_orphans = d.pop("recreate_orphans", UNSET)

        traffic = d.pop("traffic", UNSET)

        k = d.pop("k", UNSET)

        _b_score_argument = d.pop("b_score_argument", UNSET)
        b_score_argument: BScoreArgumentEnum | Unset
        if isinstance(_b_score_argument, Unset):
            b_score_argument = UNSET
        else:
            b_score_argument = check_b_score_argument_enum(_b_score_argument)

        _sort_tiebreak = d.pop("sort_tiebreak", UNSET)
        sort_tiebreak: SortTiebreakEnum | Unset
        sort_tiebreak = UNSET if isinstance(_sort_tiebreak, Unset) else check_sort_tiebreak_enum(_sort_tiebreak)

        rt_policy_request = cls(
            cluster=cluster,
            threshold_period=threshold_period,
            threshold_total=threshold_total,
            update_frequency_hz=update_frequency_hz,
            eviction_policy=eviction_policy,
            linear_resource=linear_resource,
            taint_duration_s=taint_duration_s,
            cooldown_s=cooldown_s,
            recreate_orphans=recreate_orphans,
            traffic=traffic,
            k=k,
            b_score_argument=b_score_argument,
            sort_tiebreak=sort_tiebreak,
        )

        rt_policy_request.additional_properties = d
        return rt_policy_request

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
