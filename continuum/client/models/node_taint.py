from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

T = TypeVar("T", bound="NodeTaint")


@_attrs_define
class NodeTaint:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        cluster (int):
        node (str):
        key (str):
        value (str):
        effect (str):
        event (int | None):
        created (datetime.datetime):
        expires_at (datetime.datetime):
        applied_at (datetime.datetime | None): when the API accepted it
        lifted_at (datetime.datetime | None):
        error (str):
    """

    id: int
    cluster: int
    node: str
    key: str
    value: str
    effect: str
    event: int | None
    created: datetime.datetime
    expires_at: datetime.datetime
    applied_at: datetime.datetime | None
    lifted_at: datetime.datetime | None
    error: str
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        node = self.node

        key = self.key

        value = self.value

        effect = self.effect

        event: int | None
        event = self.event

        created = self.created.isoformat()

        expires_at = self.expires_at.isoformat()

        applied_at: str | None
        applied_at = self.applied_at.isoformat() if isinstance(self.applied_at, datetime.datetime) else self.applied_at

        lifted_at: str | None
        lifted_at = self.lifted_at.isoformat() if isinstance(self.lifted_at, datetime.datetime) else self.lifted_at

        error = self.error

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "node": node,
                "key": key,
                "value": value,
                "effect": effect,
                "event": event,
                "created": created,
                "expires_at": expires_at,
                "applied_at": applied_at,
                "lifted_at": lifted_at,
                "error": error,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        node = d.pop("node")

        key = d.pop("key")

        value = d.pop("value")

        effect = d.pop("effect")

        def _parse_event(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        event = _parse_event(d.pop("event"))

        created = datetime.datetime.fromisoformat(d.pop("created"))

        expires_at = datetime.datetime.fromisoformat(d.pop("expires_at"))

        def _parse_applied_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                applied_at_type_0 = datetime.datetime.fromisoformat(data)

                return applied_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        applied_at = _parse_applied_at(d.pop("applied_at"))

        def _parse_lifted_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                lifted_at_type_0 = datetime.datetime.fromisoformat(data)

                return lifted_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        lifted_at = _parse_lifted_at(d.pop("lifted_at"))

        error = d.pop("error")

        node_taint = cls(
            id=id,
            cluster=cluster,
            node=node,
            key=key,
            value=value,
            effect=effect,
            event=event,
            created=created,
            expires_at=expires_at,
            applied_at=applied_at,
            lifted_at=lifted_at,
            error=error,
        )

        node_taint.additional_properties = d
        return node_taint

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
