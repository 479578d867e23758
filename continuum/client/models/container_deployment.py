from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar

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
    """

    container: str
    node: str
    deployment: str
    namespace: str
    state: ContainerDeploymentStateEnum
    message: str
    updated: datetime.datetime
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        container = self.container

        node = self.node

        deployment = self.deployment

        namespace = self.namespace

        state: str = self.state

        message = self.message

        updated = self.updated.isoformat()

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

        container_deployment = cls(
            container=container,
            node=node,
            deployment=deployment,
            namespace=namespace,
            state=state,
            message=message,
            updated=updated,
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
