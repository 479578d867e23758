from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

T = TypeVar("T", bound="ClusterRequest")


@_attrs_define
class ClusterRequest:
    """``fleet`` defaults to the token's fleet, or to the caller's only fleet.

    Attributes:
        name (str):
        fleet (str | Unset):
        description (str | Unset):
        kubeconfig (str | Unset):
        kube_context (str | Unset):
        namespace (str | Unset):
        default_bandwidth_mbps (float | None | Unset): bandwidth between nodes with no link path; empty means free
            transfers
        default_latency_ms (float | Unset):
    """

    name: str
    fleet: str | Unset = UNSET
    description: str | Unset = UNSET
    kubeconfig: str | Unset = UNSET
    kube_context: str | Unset = UNSET
    namespace: str | Unset = UNSET
    default_bandwidth_mbps: float | Unset | None = UNSET
    default_latency_ms: float | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        name = self.name

        fleet = self.fleet

        description = self.description

        kubeconfig = self.kubeconfig

        kube_context = self.kube_context

        namespace = self.namespace

        default_bandwidth_mbps: float | Unset | None
        if isinstance(self.default_bandwidth_mbps, Unset):
            default_bandwidth_mbps = UNSET
        else:
            default_bandwidth_mbps = self.default_bandwidth_mbps

        default_latency_ms = self.default_latency_ms

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "name": name,
            }
        )
        if fleet is not UNSET:
            field_dict["fleet"] = fleet
        if description is not UNSET:
            field_dict["description"] = description
        if kubeconfig is not UNSET:
            field_dict["kubeconfig"] = kubeconfig
        if kube_context is not UNSET:
            field_dict["kube_context"] = kube_context
        if namespace is not UNSET:
            field_dict["namespace"] = namespace
        if default_bandwidth_mbps is not UNSET:
            field_dict["default_bandwidth_mbps"] = default_bandwidth_mbps
        if default_latency_ms is not UNSET:
            field_dict["default_latency_ms"] = default_latency_ms

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        name = d.pop("name")

        fleet = d.pop("fleet", UNSET)

        description = d.pop("description", UNSET)

        kubeconfig = d.pop("kubeconfig", UNSET)

        kube_context = d.pop("kube_context", UNSET)

        namespace = d.pop("namespace", UNSET)

        def _parse_default_bandwidth_mbps(data: object) -> float | Unset | None:
            if data is None:
                return data
            if isinstance(data, Unset):
                return data
            return cast(float | Unset | None, data)

        default_bandwidth_mbps = _parse_default_bandwidth_mbps(d.pop("default_bandwidth_mbps", UNSET))

        default_latency_ms = d.pop("default_latency_ms", UNSET)

        cluster_request = cls(
            name=name,
            fleet=fleet,
            description=description,
            kubeconfig=kubeconfig,
            kube_context=kube_context,
            namespace=namespace,
            default_bandwidth_mbps=default_bandwidth_mbps,
            default_latency_ms=default_latency_ms,
        )

        cluster_request.additional_properties = d
        return cluster_request

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
