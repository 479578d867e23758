from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast
from uuid import UUID

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.decision_enum import DecisionEnum, check_decision_enum
from ..models.remap_event_status_enum import RemapEventStatusEnum, check_remap_event_status_enum
from ..models.trigger_enum import TriggerEnum, check_trigger_enum

T = TypeVar("T", bound="RemapEvent")


@_attrs_define
class RemapEvent:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        fleet (str):
        application (int):
        schedule (int):
        new_schedule (int | None):
        job (None | UUID):
        trigger (TriggerEnum): * `watch` - node watcher
            * `api` - API / dashboard
            * `what-if` - what-if
        decision (DecisionEnum): * `partial` - Partial
            * `total` - Total
        reason (str):
        failed_nodes (Any):
        lost_tasks (Any): tasks that were on the failed nodes (OT)
        moved_tasks (Any): tasks whose node changed
        reniced_tasks (Any): tasks kept on their node with a new niceness
        critical_lost (Any):
        lost_share (float): lost HEFT-rank share (0-1)
        threshold (float): total remap above this lost rank share (0-1)
        makespan_before (float):
        makespan_after (float):
        makespan_change (float):
        elapsed_ms (float): time Algorithm 2 took (decision and new mapping)
        status (RemapEventStatusEnum): * `what-if` - computed, nothing pushed
            * `applying` - being applied
            * `applied` - applied in Kubernetes
            * `not-pushed` - stored; nothing in Kubernetes to change
            * `failed` - push failed
        pods_moved (int):
        pods (Any): pods deleted and recreated when applied
        push_ms (float | None): time the changes took in Kubernetes
        message (str):
        can_apply (bool):
        created (datetime.datetime):
        applied (datetime.datetime | None):
    """

    id: int
    fleet: str
    application: int
    schedule: int
    new_schedule: int | None
    job: UUID | None
    trigger: TriggerEnum
    decision: DecisionEnum
    reason: str
    failed_nodes: Any
    lost_tasks: Any
    moved_tasks: Any
    reniced_tasks: Any
    critical_lost: Any
    lost_share: float
    threshold: float
    makespan_before: float
    makespan_after: float
    makespan_change: float
    elapsed_ms: float
    status: RemapEventStatusEnum
    pods_moved: int
    pods: Any
    push_ms: float | None
    message: str
    can_apply: bool
    created: datetime.datetime
    applied: datetime.datetime | None
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        fleet = self.fleet

        application = self.application

        schedule = self.schedule

        new_schedule: int | None
        new_schedule = self.new_schedule

        job: str | None
        job = str(self.job) if isinstance(self.job, UUID) else self.job

        trigger: str = self.trigger

        decision: str = self.decision

        reason = self.reason

        failed_nodes = self.failed_nodes

        lost_tasks = self.lost_tasks

        moved_tasks = self.moved_tasks

        reniced_tasks = self.reniced_tasks

        critical_lost = self.critical_lost

        lost_share = self.lost_share

        threshold = self.threshold

        makespan_before = self.makespan_before

        makespan_after = self.makespan_after

        makespan_change = self.makespan_change

        elapsed_ms = self.elapsed_ms

        status: str = self.status

        pods_moved = self.pods_moved

        pods = self.pods

        push_ms: float | None
        push_ms = self.push_ms

        message = self.message

        can_apply = self.can_apply

        created = self.created.isoformat()

        applied: str | None
        applied = self.applied.isoformat() if isinstance(self.applied, datetime.datetime) else self.applied

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "fleet": fleet,
                "application": application,
                "schedule": schedule,
                "new_schedule": new_schedule,
                "job": job,
                "trigger": trigger,
                "decision": decision,
                "reason": reason,
                "failed_nodes": failed_nodes,
                "lost_tasks": lost_tasks,
                "moved_tasks": moved_tasks,
                "reniced_tasks": reniced_tasks,
                "critical_lost": critical_lost,
                "lost_share": lost_share,
                "threshold": threshold,
                "makespan_before": makespan_before,
                "makespan_after": makespan_after,
                "makespan_change": makespan_change,
                "elapsed_ms": elapsed_ms,
                "status": status,
                "pods_moved": pods_moved,
                "pods": pods,
                "push_ms": push_ms,
                "message": message,
                "can_apply": can_apply,
                "created": created,
                "applied": applied,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        fleet = d.pop("fleet")

        application = d.pop("application")

        schedule = d.pop("schedule")

        def _parse_new_schedule(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        new_schedule = _parse_new_schedule(d.pop("new_schedule"))

        def _parse_job(data: object) -> UUID | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                job_type_0 = UUID(data)

                return job_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(UUID | None, data)

        job = _parse_job(d.pop("job"))

        trigger = check_trigger_enum(d.pop("trigger"))

        decision = check_decision_enum(d.pop("decision"))

        reason = d.pop("reason")

        failed_nodes = d.pop("failed_nodes")

        lost_tasks = d.pop("lost_tasks")

        moved_tasks = d.pop("moved_tasks")

        reniced_tasks = d.pop("reniced_tasks")

        critical_lost = d.pop("critical_lost")

        lost_share = d.pop("lost_share")

        threshold = d.pop("threshold")

        makespan_before = d.pop("makespan_before")

        makespan_after = d.pop("makespan_after")

        makespan_change = d.pop("makespan_change")

        elapsed_ms = d.pop("elapsed_ms")

        status = check_remap_event_status_enum(d.pop("status"))

        pods_moved = d.pop("pods_moved")

        pods = d.pop("pods")

        def _parse_push_ms(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        push_ms = _parse_push_ms(d.pop("push_ms"))

        message = d.pop("message")

        can_apply = d.pop("can_apply")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        def _parse_applied(data: object) -> datetime.datetime | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                applied_type_0 = datetime.datetime.fromisoformat(data)

                return applied_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(datetime.datetime | None, data)

        applied = _parse_applied(d.pop("applied"))

        remap_event = cls(
            id=id,
            fleet=fleet,
            application=application,
            schedule=schedule,
            new_schedule=new_schedule,
            job=job,
            trigger=trigger,
            decision=decision,
            reason=reason,
            failed_nodes=failed_nodes,
            lost_tasks=lost_tasks,
            moved_tasks=moved_tasks,
            reniced_tasks=reniced_tasks,
            critical_lost=critical_lost,
            lost_share=lost_share,
            threshold=threshold,
            makespan_before=makespan_before,
            makespan_after=makespan_after,
            makespan_change=makespan_change,
            elapsed_ms=elapsed_ms,
            status=status,
            pods_moved=pods_moved,
            pods=pods,
            push_ms=push_ms,
            message=message,
            can_apply=can_apply,
            created=created,
            applied=applied,
        )

        remap_event.additional_properties = d
        return remap_event

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
