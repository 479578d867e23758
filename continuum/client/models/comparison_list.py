from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast
from uuid import UUID

from attrs import define as _attrs_define
from attrs import field as _attrs_field

T = TypeVar("T", bound="ComparisonList")


@_attrs_define
class ComparisonList:
    """A comparison: per algorithm makespan, SLR, speedup against VisionWorks, O/XO, idle time (``figures``),
    Table 4.3's relative speeds, and links to each algorithm's stored schedule.

        Attributes:
            id (int):
            fleet (str):
            application (int):
            cluster (int | None):
            job (None | UUID):
            algorithms (Any): the algorithms compared, in the order asked
            params (Any): frames, fps/period, batch, rank_mode, comm_mode
            best (str):
            created (datetime.datetime):
    """

    id: int
    fleet: str
    application: int
    cluster: int | None
    job: UUID | None
    algorithms: Any
    params: Any
    best: str
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

        algorithms = self.algorithms

        params = self.params

        best = self.best

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
                "algorithms": algorithms,
                "params": params,
                "best": best,
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

        algorithms = d.pop("algorithms")

        params = d.pop("params")

        best = d.pop("best")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        comparison_list = cls(
            id=id,
            fleet=fleet,
            application=application,
            cluster=cluster,
            job=job,
            algorithms=algorithms,
            params=params,
            best=best,
            created=created,
        )

        comparison_list.additional_properties = d
        return comparison_list

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
