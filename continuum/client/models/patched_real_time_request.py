from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.criticality_enum import CriticalityEnum, check_criticality_enum
from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.wcet_request import WcetRequest


T = TypeVar("T", bound="PatchedRealTimeRequest")


@_attrs_define
class PatchedRealTimeRequest:
    """A RealTime object (Listing 3.33). ``wcets`` keeps the order of ``spec.rtWcets``.

    Attributes:
        cluster (int | Unset):
        namespace (str | Unset): default: the cluster's namespace
        name (str | Unset): pods link to it by label rt-scheduling
        criticality (CriticalityEnum | Unset): * `A` - A
            * `B` - B
            * `C` - C
            * `D` - D
        period (float | Unset): rtPeriod, ms
        deadline (float | Unset): rtDeadline, ms
        wcets (list[WcetRequest] | Unset):
        stateless (bool | Unset): may be evicted and re-created elsewhere
        cpu (float | Unset): CPU request, cores
        memory_mib (float | Unset): memory request, MiB
        warmup_ms (float | None | Unset): ms after exec whose overruns are start-up, not misses (null: the agent's
            default, 20 periods)
    """

    cluster: int | Unset = UNSET
    namespace: str | Unset = UNSET
    name: str | Unset = UNSET
    criticality: CriticalityEnum | Unset = UNSET
    period: float | Unset = UNSET
    deadline: float | Unset = UNSET
    wcets: list[WcetRequest] | Unset = UNSET
    stateless: bool | Unset = UNSET
    cpu: float | Unset = UNSET
    memory_mib: float | Unset = UNSET
    warmup_ms: float | Unset | None = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        cluster = self.cluster

        namespace = self.namespace

        name = self.name

        criticality: str | Unset = UNSET
        if not isinstance(self.criticality, Unset):
            criticality = self.criticality

        period = self.period

        deadline = self.deadline

        wcets: list[dict[str, Any]] | Unset = UNSET
        if not isinstance(self.wcets, Unset):
            wcets = []
            for wcets_item_data in self.wcets:
                wcets_item = wcets_item_data.to_dict()
                wcets.append(wcets_item)

        stateless = self.stateless

        cpu = self.cpu

        memory_mib = self.memory_mib

        warmup_ms: float | Unset | None
        warmup_ms = UNSET if isinstance(self.warmup_ms, Unset) else self.warmup_ms

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update({})
        if cluster is not UNSET:
            field_dict["cluster"] = cluster
        if namespace is not UNSET:
            field_dict["namespace"] = namespace
        if name is not UNSET:
            field_dict["name"] = name
        if criticality is not UNSET:
            field_dict["criticality"] = criticality
        if period is not UNSET:
            field_dict["period"] = period
        if deadline is not UNSET:
            field_dict["deadline"] = deadline
        if wcets is not UNSET:
            field_dict["wcets"] = wcets
        if stateless is not UNSET:
            field_dict["stateless"] = stateless
        if cpu is not UNSET:
            field_dict["cpu"] = cpu
        if memory_mib is not UNSET:
            field_dict["memory_mib"] = memory_mib
        if warmup_ms is not UNSET:
            field_dict["warmup_ms"] = warmup_ms

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.wcet_request import WcetRequest

        d = dict(src_dict)
        cluster = d.pop("cluster", UNSET)

        namespace = d.pop("namespace", UNSET)

        name = d.pop("name", UNSET)

        _criticality = d.pop("criticality", UNSET)
        criticality: CriticalityEnum | Unset
        criticality = UNSET if isinstance(_criticality, Unset) else check_criticality_enum(_criticality)

        period = d.pop("period", UNSET)

        deadline = d.pop("deadline", UNSET)

        _wcets = d.pop("wcets", UNSET)
        wcets: list[WcetRequest] | Unset = UNSET
        if _wcets is not UNSET:
            wcets = []
            for wcets_item_data in _wcets:
                wcets_item = WcetRequest.from_dict(wcets_item_data)

                wcets.append(wcets_item)

        stateless = d.pop("stateless", UNSET)

        cpu = d.pop("cpu", UNSET)

        memory_mib = d.pop("memory_mib", UNSET)

        def _parse_warmup_ms(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        warmup_ms = _parse_warmup_ms(d.pop("warmup_ms", UNSET))

        patched_real_time_request = cls(
            cluster=cluster,
            namespace=namespace,
            name=name,
            criticality=criticality,
            period=period,
            deadline=deadline,
            wcets=wcets,
            stateless=stateless,
            cpu=cpu,
            memory_mib=memory_mib,
            warmup_ms=warmup_ms,
        )

        patched_real_time_request.additional_properties = d
        return patched_real_time_request

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
