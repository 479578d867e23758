from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.rt_event_kind_enum import RTEventKindEnum, check_rt_event_kind_enum

T = TypeVar("T", bound="RTEvent")


@_attrs_define
class RTEvent:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        cluster (int):
        kind (RTEventKindEnum): * `eviction` - Eviction
            * `alert` - Alert
        node (str):
        container (str): the violating container
        pod (str): the violating pod (namespace/name)
        trigger (str):
        missed_period (int):
        missed_total (int):
        victim (str): evicted pod (namespace/name)
        policy (str):
        candidates (Any):
        message (str):
        decision (Any): the engine's ReconcileDecision.to_dict()
        miss_at (datetime.datetime | None):
        sent_at (datetime.datetime | None):
        received_at (datetime.datetime):
        reconcile_done_at (datetime.datetime | None):
        eviction_sent_at (datetime.datetime | None):
        eviction_done_at (datetime.datetime | None):
        eviction_error (str):
        recreated (str): the replacement pod we created, if any
        response (Any): Eq. 3.19 components in ms
        response_ms (float | None): report received to eviction sent, ms
    """

    id: int
    cluster: int
    kind: RTEventKindEnum
    node: str
    container: str
    pod: str
    trigger: str
    missed_period: int
    missed_total: int
    victim: str
    policy: str
    candidates: Any
    message: str
    decision: Any
    miss_at: datetime.datetime | None
    sent_at: datetime.datetime | None
    received_at: datetime.datetime
    reconcile_done_at: datetime.datetime | None
    eviction_sent_at: datetime.datetime | None
    eviction_done_at: datetime.datetime | None
    eviction_error: str
    recreated: str
    response: Any
    response_ms: float | None
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        kind: str = self.kind

        node = self.node

        container = self.container

        pod = self.pod

        trigger = self.trigger

        missed_period = self.missed_period

        missed_total = self.missed_total

        victim = self.victim

        policy = self.policy

        candidates = self.candidates

        message = self.message

        decision = self.decision

        miss_at: str | None
        miss_at = self.miss_at.isoformat() if isinstance(self.miss_at, datetime.datetime) else self.miss_at

        sent_at: str | None
        sent_at = self.sent_at.isoformat() if isinstance(self.sent_at, datetime.datetime) else self.sent_at

        received_at = self.received_at.isoformat()

        reconcile_done_at: str | None
        if isinstance(self.reconcile_done_at, datetime.datetime):
            reconcile_done_at = self.reconcile_done_at.isoformat()
        else:
            reconcile_done_at = self.reconcile_done_at

        eviction_sent_at: str | None
        if isinstance(self.eviction_sent_at, datetime.datetime):
            eviction_sent_at = self.eviction_sent_at.isoformat()
        else:
            eviction_sent_at = self.eviction_sent_at

        eviction_done_at: str | None
        if isinstance(self.eviction_done_at, datetime.datetime):
            eviction_done_at = self.eviction_done_at.isoformat()
        else:
            eviction_done_at = self.eviction_done_at

        eviction_error = self.eviction_error

        recreated = self.recreated

        response = self.response

        response_ms: float | None
        response_ms = self.response_ms

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "kind": kind,
                "node": node,
                "container": container,
                "pod": pod,
                "trigger": trigger,
                "missed_period": missed_period,
                "missed_total": missed_total,
                "victim": victim,
                "policy": policy,
                "candidates": candidates,
                "message": message,
                "decision": decision,
                "miss_at": miss_at,
                "sent_at": sent_at,
                "received_at": received_at,
                "reconcile_done_at": reconcile_done_at,
                "eviction_sent_at": eviction_sent_at,
                "eviction_done_at": eviction_done_at,
                "eviction_error": eviction_error,
                "recreated": recreated,
                "response": response,
                "response_ms": response_ms,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        kind = check_rt_event_kind_enum(d.pop("kind"))

        node = d.pop("node")

        container = d.pop("container")

        pod = d.pop("pod")

        trigger = d.pop("trigger")

        missed_period = d.pop("missed_period")

        missed_total = d.pop("missed_total")

        victim = d.pop("victim")

        policy = d.pop("policy")

        candidates = d.pop("candidates")

        message = d.pop("message")

        decision = d.pop("decision")

        def _parse_miss_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                miss_at_type_0 = datetime.datetime.fromisoformat(data)

                return miss_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        miss_at = _parse_miss_at(d.pop("miss_at"))

        def _parse_sent_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                sent_at_type_0 = datetime.datetime.fromisoformat(data)

                return sent_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        sent_at = _parse_sent_at(d.pop("sent_at"))

        received_at = datetime.datetime.fromisoformat(d.pop("received_at"))

        def _parse_reconcile_done_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                reconcile_done_at_type_0 = datetime.datetime.fromisoformat(data)

                return reconcile_done_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        reconcile_done_at = _parse_reconcile_done_at(d.pop("reconcile_done_at"))

        def _parse_eviction_sent_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                eviction_sent_at_type_0 = datetime.datetime.fromisoformat(data)

                return eviction_sent_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        eviction_sent_at = _parse_eviction_sent_at(d.pop("eviction_sent_at"))

        def _parse_eviction_done_at(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                eviction_done_at_type_0 = datetime.datetime.fromisoformat(data)

                return eviction_done_at_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        eviction_done_at = _parse_eviction_done_at(d.pop("eviction_done_at"))

        eviction_error = d.pop("eviction_error")

        recreated = d.pop("recreated")

        response = d.pop("response")

        def _parse_response_ms(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        response_ms = _parse_response_ms(d.pop("response_ms"))

        rt_event = cls(
            id=id,
            cluster=cluster,
            kind=kind,
            node=node,
            container=container,
            pod=pod,
            trigger=trigger,
            missed_period=missed_period,
            missed_total=missed_total,
            victim=victim,
            policy=policy,
            candidates=candidates,
            message=message,
            decision=decision,
            miss_at=miss_at,
            sent_at=sent_at,
            received_at=received_at,
            reconcile_done_at=reconcile_done_at,
            eviction_sent_at=eviction_sent_at,
            eviction_done_at=eviction_done_at,
            eviction_error=eviction_error,
            recreated=recreated,
            response=response,
            response_ms=response_ms,
        )

        rt_event.additional_properties = d
        return rt_event

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
