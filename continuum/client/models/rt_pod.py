from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

T = TypeVar("T", bound="RTPod")


@_attrs_define
class RTPod:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        cluster (int):
        namespace (str):
        name (str):
        uid (str):
        node (str): empty while pending
        container_name (str):
        scheduler_name (str):
        realtime (int | None):
        criticality (str):
        stateless (bool):
        cpu (float):
        memory_mib (float):
        utilization (float | None): WCET(node)/P where bound
        owned (bool): a controller (ReplicaSet, ...) owns it
        phase (str):
        bound_at (datetime.datetime | None):
        deleted_at (datetime.datetime | None):
        pod_event (str): the pod's newest event: reason: message
        pod_state_at (datetime.datetime | None): when the watcher last stored a change
    """

    id: int
    cluster: int
    namespace: str
    name: str
    uid: str
    node: str
    container_name: str
    scheduler_name: str
    realtime: int | None
    criticality: str
    stateless: bool
    cpu: float
    memory_mib: float
    utilization: float | None
    owned: bool
    phase: str
    bound_at: datetime.datetime | None
    deleted_at: datetime.datetime | None
    pod_event: str
    pod_state_at: datetime.datetime | None
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        namespace = self.namespace

        name = self.name

        uid = self.uid

        node = self.node

        container_name = self.container_name

        scheduler_name = self.scheduler_name

        realtime: int | None
        realtime = self.realtime

        criticality = self.criticality

        stateless = self.stateless

        cpu = self.cpu

        memory_mib = self.memory_mib

        utilization: float | None
        utilization = self.utilization

        owned = self.owned

        phase = self.phase

        bound_at: str | None
        bound_at = self.bound_at.isoformat() if isinstance(self.bound_at, datetime.datetime) else self.bound_at

        deleted_at: str | None
        deleted_at = self.deleted_at.isoformat() if isinstance(self.deleted_at, datetime.datetime) else self.deleted_at

        pod_event = self.pod_event

        pod_state_at: str | None
        if isinstance(self.pod_state_at, datetime.datetime):
            pod_state_at = self.pod_state_at.isoformat()
        else:
            pod_state_at = self.pod_state_at

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "namespace": namespace,
                "name": name,
                "uid": uid,
                "node": node,
                "container_name": container_name,
                "scheduler_name": scheduler_name,
                "realtime": realtime,
                "criticality": criticality,
                "stateless": stateless,
                "cpu": cpu,
                "memory_mib": memory_mib,
                "utilization": utilization,
                "owned": owned,
                "phase": phase,
                "bound_at": bound_at,
                "deleted_at": deleted_at,
                "pod_event": pod_event,
                "pod_state_at": pod_state_at,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        namespace = d.pop("namespace")

        name = d.pop("name")

        uid = d.pop("uid")

        node = d.pop("node")

        container_name = d.pop("container_name")

        scheduler_name = d.pop("scheduler_name")

        def _parse_realtime(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        realtime = _parse_realtime(d.pop("realtime"))

        criticality = d.pop("criticality")

        stateless = d.pop("stateless")

        cpu = d.pop("cpu")

        memory_mib = d.pop("memory_mib")

        def _parse_utilization(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        utilization = _parse_utilization(d.pop("utilization"))

        owned = d.pop("owned")

        phase = d.pop("phase")

        def _parse_bound_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                bound_at_type_0 = datetime.datetime.fromisoformat(data)

                return bound_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        bound_at = _parse_bound_at(d.pop("bound_at"))

        def _parse_deleted_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                deleted_at_type_0 = datetime.datetime.fromisoformat(data)

                return deleted_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        deleted_at = _parse_deleted_at(d.pop("deleted_at"))

        pod_event = d.pop("pod_event")

        def _parse_pod_state_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                pod_state_at_type_0 = datetime.datetime.fromisoformat(data)

                return pod_state_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        pod_state_at = _parse_pod_state_at(d.pop("pod_state_at"))

        rt_pod = cls(
            id=id,
            cluster=cluster,
            namespace=namespace,
            name=name,
            uid=uid,
            node=node,
            container_name=container_name,
            scheduler_name=scheduler_name,
            realtime=realtime,
            criticality=criticality,
            stateless=stateless,
            cpu=cpu,
            memory_mib=memory_mib,
            utilization=utilization,
            owned=owned,
            phase=phase,
            bound_at=bound_at,
            deleted_at=deleted_at,
            pod_event=pod_event,
            pod_state_at=pod_state_at,
        )

        rt_pod.additional_properties = d
        return rt_pod

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
