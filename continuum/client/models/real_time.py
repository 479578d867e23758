from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.criticality_enum import CriticalityEnum, check_criticality_enum
from ..models.sync_state_enum import SyncStateEnum, check_sync_state_enum
from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.real_time_utilization import RealTimeUtilization
    from ..models.wcet import Wcet


T = TypeVar("T", bound="RealTime")


@_attrs_define
class RealTime:
    """A RealTime object (Listing 3.33). ``wcets`` keeps the order of ``spec.rtWcets``.

    Attributes:
        id (int):
        cluster (int):
        name (str): pods link to it by label rt-scheduling
        criticality (CriticalityEnum): * `A` - A
            * `B` - B
            * `C` - C
            * `D` - D
        period (float): rtPeriod, ms
        deadline (float): rtDeadline, ms
        wcets (list[Wcet]):
        utilization (RealTimeUtilization): WCET(node) / period per node
        sync_state (SyncStateEnum): * `local` - not in Kubernetes
            * `synced` - in sync
            * `error` - sync failed
        sync_error (str):
        uid (str):
        resource_version (str):
        created (datetime.datetime):
        updated (datetime.datetime):
        namespace (str | Unset): default: the cluster's namespace
        stateless (bool | Unset): may be evicted and re-created elsewhere
        cpu (float | Unset): CPU request, cores
        memory_mib (float | Unset): memory request, MiB
        warmup_ms (float | None | Unset): ms after exec whose overruns are start-up, not misses (null: the agent's
            default, 20 periods)
    """

    id: int
    cluster: int
    name: str
    criticality: CriticalityEnum
    period: float
    deadline: float
    wcets: list[Wcet]
    utilization: RealTimeUtilization
    sync_state: SyncStateEnum
    sync_error: str
    uid: str
    resource_version: str
    created: datetime.datetime
    updated: datetime.datetime
    namespace: str | Unset = UNSET
    stateless: bool | Unset = UNSET
    cpu: float | Unset = UNSET
    memory_mib: float | Unset = UNSET
    warmup_ms: float | Unset | None = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        name = self.name

        criticality: str = self.criticality

        period = self.period

        deadline = self.deadline

        wcets = []
        for wcets_item_data in self.wcets:
            wcets_item = wcets_item_data.to_dict()
            wcets.append(wcets_item)

        utilization = self.utilization.to_dict()

        sync_state: str = self.sync_state

        sync_error = self.sync_error

        uid = self.uid

        resource_version = self.resource_version

        created = self.created.isoformat()

        updated = self.updated.isoformat()

        namespace = self.namespace

        stateless = self.stateless

        cpu = self.cpu

        memory_mib = self.memory_mib

        warmup_ms: float | Unset | None
        warmup_ms = UNSET if isinstance(self.warmup_ms, Unset) else self.warmup_ms

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "name": name,
                "criticality": criticality,
                "period": period,
                "deadline": deadline,
                "wcets": wcets,
                "utilization": utilization,
                "sync_state": sync_state,
                "sync_error": sync_error,
                "uid": uid,
                "resource_version": resource_version,
                "created": created,
                "updated": updated,
            }
        )
        if namespace is not UNSET:
            field_dict["namespace"] = namespace
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
        from ..models.real_time_utilization import RealTimeUtilization
        from ..models.wcet import Wcet

        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        name = d.pop("name")

        criticality = check_criticality_enum(d.pop("criticality"))

        period = d.pop("period")

        deadline = d.pop("deadline")

        wcets = []
        _wcets = d.pop("wcets")
        for wcets_item_data in _wcets:
            wcets_item = Wcet.from_dict(wcets_item_data)

            wcets.append(wcets_item)

        utilization = RealTimeUtilization.from_dict(d.pop("utilization"))

        sync_state = check_sync_state_enum(d.pop("sync_state"))

        sync_error = d.pop("sync_error")

        uid = d.pop("uid")

        resource_version = d.pop("resource_version")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        updated = datetime.datetime.fromisoformat(d.pop("updated"))

        namespace = d.pop("namespace", UNSET)

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

        real_time = cls(
            id=id,
            cluster=cluster,
            name=name,
            criticality=criticality,
            period=period,
            deadline=deadline,
            wcets=wcets,
            utilization=utilization,
            sync_state=sync_state,
            sync_error=sync_error,
            uid=uid,
            resource_version=resource_version,
            created=created,
            updated=updated,
            namespace=namespace,
            stateless=stateless,
            cpu=cpu,
            memory_mib=memory_mib,
            warmup_ms=warmup_ms,
        )

        real_time.additional_properties = d
        return real_time

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
