from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast
from uuid import UUID

from attrs import define as _attrs_define
from attrs import field as _attrs_field

T = TypeVar("T", bound="ScheduleList")


@_attrs_define
class ScheduleList:
    """A stored schedule in a list: its small columns only (never its assignments, ranks or platform).

    Attributes:
        id (int):
        fleet (str):
        application (int):
        cluster (int | None):
        job (None | UUID):
        algorithm (str):
        makespan (float):
        created (datetime.datetime):
    """

    id: int
    fleet: str
    application: int
    cluster: int | None
    job: UUID | None
    algorithm: str
    makespan: float
    created: datetime.datetime
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        fleet = self.fleet

        application = self.application

        cluster: int | None
        cluster = self.cluster

        job: str | None
        job = str(self.job) if isinstance(self.job, UUID) else self.job

        algorithm = self.algorithm

        makespan = self.makespan

        created = self.created.isoformat()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "fleet": fleet,
                "application": application,
                "cluster": cluster,
                "job": job,
                "algorithm": algorithm,
                "makespan": makespan,
                "created": created,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        fleet = d.pop("fleet")

        application = d.pop("application")

        def _parse_cluster(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        cluster = _parse_cluster(d.pop("cluster"))

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

        algorithm = d.pop("algorithm")

        makespan = d.pop("makespan")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        schedule_list = cls(
            id=id,
            fleet=fleet,
            application=application,
            cluster=cluster,
            job=job,
            algorithm=algorithm,
            makespan=makespan,
            created=created,
        )

        schedule_list.additional_properties = d
        return schedule_list

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
