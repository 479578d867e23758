from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.arch_enum import ArchEnum, check_arch_enum
from ..models.blank_enum import BlankEnum, check_blank_enum
from ..models.capacity_source_enum import CapacitySourceEnum, check_capacity_source_enum
from ..models.compute_node_status_enum import ComputeNodeStatusEnum, check_compute_node_status_enum
from ..models.criticality_enum import CriticalityEnum, check_criticality_enum
from ..types import UNSET, Unset

T = TypeVar("T", bound="ComputeNode")


@_attrs_define
class ComputeNode:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        cluster (int):
        name (str):
        capacity_source (CapacitySourceEnum): * `declared` - Declared
            * `reported` - Reported
        reported_cpu (float | None): CPU cores Kubernetes reports (capacity)
        reported_memory_mib (int | None): memory Kubernetes reports
        reported_storage_mib (int | None): storage Kubernetes reports
        arch (ArchEnum | Unset): * `amd64` - Amd64
            * `arm64` - Arm64
            * `riscv64` - Riscv64
        cpu (float | Unset): CPU cores
        memory_mib (int | Unset):
        storage_mib (int | Unset):
        accelerators (list[str] | Unset): e.g. ["igpu"]
        processor_class (str | Unset): class that DAG task costs name (cpu, gpu, ...)
        speed (float | Unset): class cost / speed
        rt (bool | Unset): real-time capable
        criticality (BlankEnum | CriticalityEnum | Unset):
        rt_threshold (float | None | Unset): admissible RT utilization (M x 0.95)
        labels (Any | Unset):
        taints (Any | Unset): [{"key", "value", "effect"}]
        status (ComputeNodeStatusEnum | Unset): * `Ready` - Ready
            * `NotReady` - Not Ready
            * `Unknown` - Unknown
    """

    id: int
    cluster: int
    name: str
    capacity_source: CapacitySourceEnum
    reported_cpu: float | None
    reported_memory_mib: int | None
    reported_storage_mib: int | None
    arch: ArchEnum | Unset = UNSET
    cpu: float | Unset = UNSET
    memory_mib: int | Unset = UNSET
    storage_mib: int | Unset = UNSET
    accelerators: list[str] | Unset = UNSET
    processor_class: str | Unset = UNSET
    speed: float | Unset = UNSET
    rt: bool | Unset = UNSET
    criticality: BlankEnum | CriticalityEnum | Unset = UNSET
    rt_threshold: float | Unset | None = UNSET
    labels: Any | Unset = UNSET
    taints: Any | Unset = UNSET
    status: ComputeNodeStatusEnum | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        name = self.name

        capacity_source: str = self.capacity_source

        reported_cpu: float | None
        reported_cpu = self.reported_cpu

        reported_memory_mib: int | None
        reported_memory_mib = self.reported_memory_mib

        reported_storage_mib: int | None
        reported_storage_mib = self.reported_storage_mib

        arch: str | Unset = UNSET
        if not isinstance(self.arch, Unset):
            arch = self.arch

        cpu = self.cpu

        memory_mib = self.memory_mib

        storage_mib = self.storage_mib

        accelerators: list[str] | Unset = UNSET
        if not isinstance(self.accelerators, Unset):
            accelerators = self.accelerators

        processor_class = self.processor_class

        speed = self.speed

        rt = self.rt

        criticality: str | Unset
        if isinstance(self.criticality, Unset):
            criticality = UNSET
        elif isinstance(self.criticality, str):
            criticality = self.criticality
        else:
            criticality = self.criticality

        rt_threshold: float | Unset | None
        rt_threshold = UNSET if isinstance(self.rt_threshold, Unset) else self.rt_threshold

        labels = self.labels

        taints = self.taints

        status: str | Unset = UNSET
        if not isinstance(self.status, Unset):
            status = self.status

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "name": name,
                "capacity_source": capacity_source,
                "reported_cpu": reported_cpu,
                "reported_memory_mib": reported_memory_mib,
                "reported_storage_mib": reported_storage_mib,
            }
        )
        if arch is not UNSET:
            field_dict["arch"] = arch
        if cpu is not UNSET:
            field_dict["cpu"] = cpu
        if memory_mib is not UNSET:
            field_dict["memory_mib"] = memory_mib
        if storage_mib is not UNSET:
            field_dict["storage_mib"] = storage_mib
        if accelerators is not UNSET:
            field_dict["accelerators"] = accelerators
        if processor_class is not UNSET:
            field_dict["processor_class"] = processor_class
        if speed is not UNSET:
            field_dict["speed"] = speed
        if rt is not UNSET:
            field_dict["rt"] = rt
        if criticality is not UNSET:
            field_dict["criticality"] = criticality
        if rt_threshold is not UNSET:
            field_dict["rt_threshold"] = rt_threshold
        if labels is not UNSET:
            field_dict["labels"] = labels
        if taints is not UNSET:
            field_dict["taints"] = taints
        if status is not UNSET:
            field_dict["status"] = status

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        name = d.pop("name")

        capacity_source = check_capacity_source_enum(d.pop("capacity_source"))

        def _parse_reported_cpu(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        reported_cpu = _parse_reported_cpu(d.pop("reported_cpu"))

        def _parse_reported_memory_mib(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        reported_memory_mib = _parse_reported_memory_mib(d.pop("reported_memory_mib"))

        def _parse_reported_storage_mib(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        reported_storage_mib = _parse_reported_storage_mib(d.pop("reported_storage_mib"))

        _arch = d.pop("arch", UNSET)
        arch: ArchEnum | Unset
        arch = UNSET if isinstance(_arch, Unset) else check_arch_enum(_arch)

        cpu = d.pop("cpu", UNSET)

        memory_mib = d.pop("memory_mib", UNSET)

        storage_mib = d.pop("storage_mib", UNSET)

        accelerators = cast(list[str], d.pop("accelerators", UNSET))

        processor_class = d.pop("processor_class", UNSET)

        speed = d.pop("speed", UNSET)

        rt = d.pop("rt", UNSET)

        def _parse_criticality(data: object) -> BlankEnum | CriticalityEnum | Unset:
            if isinstance(data, Unset):
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                criticality_type_0 = check_criticality_enum(data)

                return criticality_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            if not isinstance(data, str):
                raise TypeError()
            criticality_type_1 = check_blank_enum(data)

            return criticality_type_1

        criticality = _parse_criticality(d.pop("criticality", UNSET))

        def _parse_rt_threshold(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        rt_threshold = _parse_rt_threshold(d.pop("rt_threshold", UNSET))

        labels = d.pop("labels", UNSET)

        taints = d.pop("taints", UNSET)

        _status = d.pop("status", UNSET)
        status: ComputeNodeStatusEnum | Unset
        status = UNSET if isinstance(_status, Unset) else check_compute_node_status_enum(_status)

        compute_node = cls(
            id=id,
            cluster=cluster,
            name=name,
            capacity_source=capacity_source,
            reported_cpu=reported_cpu,
            reported_memory_mib=reported_memory_mib,
            reported_storage_mib=reported_storage_mib,
            arch=arch,
            cpu=cpu,
            memory_mib=memory_mib,
            storage_mib=storage_mib,
            accelerators=accelerators,
            processor_class=processor_class,
            speed=speed,
            rt=rt,
            criticality=criticality,
            rt_threshold=rt_threshold,
            labels=labels,
            taints=taints,
            status=status,
        )

        compute_node.additional_properties = d
        return compute_node

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
