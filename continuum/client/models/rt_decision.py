from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.outcome_enum import OutcomeEnum, check_outcome_enum

T = TypeVar("T", bound="RTDecision")


@_attrs_define
class RTDecision:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        cluster (int):
        plan (int | None):
        namespace (str):
        pod (str):
        pod_uid (str):
        realtime (int | None):
        criticality (str):
        outcome (OutcomeEnum): * `bound` - Bound
            * `pending` - Pending
            * `failed` - bind failed
        node (str):
        score (float | None):
        message (str):
        decision (Any): Decision.to_dict(): every node's filter or score on a small cluster, else the top candidates, an
            example per filter and the count of nodes per filter (rejections)
        created (datetime.datetime):
    """

    id: int
    cluster: int
    plan: int | None
    namespace: str
    pod: str
    pod_uid: str
    realtime: int | None
    criticality: str
    outcome: OutcomeEnum
    node: str
    score: float | None
    message: str
    decision: Any
    created: datetime.datetime
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        plan: int | None
        plan = self.plan

        namespace = self.namespace

        pod = self.pod

        pod_uid = self.pod_uid

        realtime: int | None
        realtime = self.realtime

        criticality = self.criticality

        outcome: str = self.outcome

        node = self.node

        score: float | None
        score = self.score

        message = self.message

        decision = self.decision

        created = self.created.isoformat()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "plan": plan,
                "namespace": namespace,
                "pod": pod,
                "pod_uid": pod_uid,
                "realtime": realtime,
                "criticality": criticality,
                "outcome": outcome,
                "node": node,
                "score": score,
                "message": message,
                "decision": decision,
                "created": created,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        def _parse_plan(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        plan = _parse_plan(d.pop("plan"))

        namespace = d.pop("namespace")

        pod = d.pop("pod")

        pod_uid = d.pop("pod_uid")

        def _parse_realtime(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        realtime = _parse_realtime(d.pop("realtime"))

        criticality = d.pop("criticality")

        outcome = check_outcome_enum(d.pop("outcome"))

        node = d.pop("node")

        def _parse_score(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        score = _parse_score(d.pop("score"))

        message = d.pop("message")

        decision = d.pop("decision")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        rt_decision = cls(
            id=id,
            cluster=cluster,
            plan=plan,
            namespace=namespace,
            pod=pod,
            pod_uid=pod_uid,
            realtime=realtime,
            criticality=criticality,
            outcome=outcome,
            node=node,
            score=score,
            message=message,
            decision=decision,
            created=created,
        )

        rt_decision.additional_properties = d
        return rt_decision

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
