from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast
from uuid import UUID

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.rt_plan_kind_enum import RTPlanKindEnum, check_rt_plan_kind_enum

T = TypeVar("T", bound="RTPlan")


@_attrs_define
class RTPlan:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        cluster (int):
        kind (RTPlanKindEnum): * `whatif` - what-if
            * `scheduler` - scheduler cycle
        job (None | UUID):
        placed (int):
        pending (int):
        plan (Any): the engine's PlacementPlan.to_dict() with its decisions' (bounded) explanation and the explain table
            of their verdicts
        created (datetime.datetime):
    """

    id: int
    cluster: int
    kind: RTPlanKindEnum
    job: UUID | None
    placed: int
    pending: int
    plan: Any
    created: datetime.datetime
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        kind: str = self.kind

        job: str | None
        job = str(self.job) if isinstance(self.job, UUID) else self.job

        placed = self.placed

        pending = self.pending

        plan = self.plan

        created = self.created.isoformat()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "kind": kind,
                "job": job,
                "placed": placed,
                "pending": pending,
                "plan": plan,
                "created": created,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        kind = check_rt_plan_kind_enum(d.pop("kind"))

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

        placed = d.pop("placed")

        pending = d.pop("pending")

        plan = d.pop("plan")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        rt_plan = cls(
            id=id,
            cluster=cluster,
            kind=kind,
            job=job,
            placed=placed,
            pending=pending,
            plan=plan,
            created=created,
        )

        rt_plan.additional_properties = d
        return rt_plan

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
