from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.container_deployment_state_enum import ContainerDeploymentStateEnum, check_container_deployment_state_enum

T = TypeVar("T", bound="ContainerDeployment")


@_attrs_define
class ContainerDeployment:
    """The base of every model serializer of the API.

    Attributes:
        container (str):
        node (str):
        deployment (str):
        namespace (str):
        state (ContainerDeploymentStateEnum): * `not_pushed` - Not Pushed
            * `applied` - Applied
            * `failed` - Failed
            * `superseded` - Superseded
        message (str):
        updated (datetime.datetime):
        pod_name (str):
        pod_phase (str): Pending, Running, ..., Deleted
        pod_node (str): the node the pod is bound to
        pod_event (str): the pod's newest event: reason: message
        pod_state_at (datetime.datetime | None): when the watcher last stored a change
    """

    container: str
    node: str
    deployment: str
    namespace: str
    state: ContainerDeploymentStateEnum
    message: str
    updated: datetime.datetime
    pod_name: str
    pod_phase: str
    pod_node: str
    pod_event: str
    pod_state_at: datetime.datetime | None
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        container = self.container

        node = self.node

        deployment = self.deployment

        namespace = self.namespace

        state: str = self.state

        message = self.message

        updated = self.updated.isoformat()

        pod_name = self.pod_name

        pod_phase = self.pod_phase

        pod_node = self.pod_node

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
                "container": container,
                "node": node,
                "deployment": deployment,
                "namespace": namespace,
                "state": state,
                "message": message,
                "updated": updated,
                "pod_name": pod_name,
                "pod_phase": pod_phase,
                "pod_node": pod_node,
                "pod_event": pod_event,
                "pod_state_at": pod_state_at,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        container = d.pop("container")

        node = d.pop("node")

        deployment = d.pop("deployment")

        namespace = d.pop("namespace")

        state = check_container_deployment_state_enum(d.pop("state"))

        message = d.pop("message")

        updated = datetime.datetime.fromisoformat(d.pop("updated"))

        pod_name = d.pop("pod_name")

        pod_phase = d.pop("pod_phase")

        pod_node = d.pop("pod_node")

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

        container_deployment = cls(
            container=container,
            node=node,
            deployment=deployment,
            namespace=namespace,
            state=state,
            message=message,
            updated=updated,
            pod_name=pod_name,
            pod_phase=pod_phase,
            pod_node=pod_node,
            pod_event=pod_event,
            pod_state_at=pod_state_at,
        )

        container_deployment.additional_properties = d
        return container_deployment

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
