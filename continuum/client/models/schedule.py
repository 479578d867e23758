from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast
from uuid import UUID

from attrs import define as _attrs_define
from attrs import field as _attrs_field

if TYPE_CHECKING:
    from ..models.assignment import Assignment


T = TypeVar("T", bound="Schedule")


@_attrs_define
class Schedule:
    """A stored schedule in the ``continuum.schedule/v1`` shape, plus its placement status per task.

    Bounded: ``assignments`` holds the first :data:`MAX_INLINE_ASSIGNMENTS` (in start order);
    ``assignment_count`` says how many there are, ``assignments_complete`` whether all are inline, and
    ``assignments_url`` lists them all, paginated and filterable.

        Attributes:
            id (int):
            format_ (str):
            fleet (str):
            application (int):
            cluster (int | None):
            job (None | UUID):
            comparison (int | None): the comparison that made this schedule, if any
            algorithm (str):
            params (Any):
            makespan (float):
            ranks (Any):
            metrics (Any):
            platform (Any): the platform scheduled on, as continuum.platform/v1
            assignments (list[Assignment]):
            assignment_count (int):
            assignments_complete (bool):
            assignments_url (str):
            created (datetime.datetime):
    """

    id: int
    format_: str
    fleet: str
    application: int
    cluster: int | None
    job: UUID | None
    comparison: int | None
    algorithm: str
    params: Any
    makespan: float
    ranks: Any
    metrics: Any
    platform: Any
    assignments: list[Assignment]
    assignment_count: int
    assignments_complete: bool
    assignments_url: str
    created: datetime.datetime
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        format_ = self.format_

        fleet = self.fleet

        application = self.application

        cluster: int | None
        cluster = self.cluster

        job: str | None
        job = str(self.job) if isinstance(self.job, UUID) else self.job

        comparison: int | None
        comparison = self.comparison

        algorithm = self.algorithm

        params = self.params

        makespan = self.makespan

        ranks = self.ranks

        metrics = self.metrics

        platform = self.platform

        assignments = []
        for assignments_item_data in self.assignments:
            assignments_item = assignments_item_data.to_dict()
            assignments.append(assignments_item)

        assignment_count = self.assignment_count

        assignments_complete = self.assignments_complete

        assignments_url = self.assignments_url

        created = self.created.isoformat()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "format": format_,
                "fleet": fleet,
                "application": application,
                "cluster": cluster,
                "job": job,
                "comparison": comparison,
                "algorithm": algorithm,
                "params": params,
                "makespan": makespan,
                "ranks": ranks,
                "metrics": metrics,
                "platform": platform,
                "assignments": assignments,
                "assignment_count": assignment_count,
                "assignments_complete": assignments_complete,
                "assignments_url": assignments_url,
                "created": created,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.assignment import Assignment

        d = dict(src_dict)
        id = d.pop("id")

        format_ = d.pop("format")

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

        def _parse_comparison(data: object) -> int | None:
            if data is None:
                return data
            return cast(int | None, data)

        comparison = _parse_comparison(d.pop("comparison"))

        algorithm = d.pop("algorithm")

        params = d.pop("params")

        makespan = d.pop("makespan")

        ranks = d.pop("ranks")

        metrics = d.pop("metrics")

        platform = d.pop("platform")

        assignments = []
        _assignments = d.pop("assignments")
        for assignments_item_data in _assignments:
            assignments_item = Assignment.from_dict(assignments_item_data)

            assignments.append(assignments_item)

        assignment_count = d.pop("assignment_count")

        assignments_complete = d.pop("assignments_complete")

        assignments_url = d.pop("assignments_url")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        schedule = cls(
            id=id,
            format_=format_,
            fleet=fleet,
            application=application,
            cluster=cluster,
            job=job,
            comparison=comparison,
            algorithm=algorithm,
            params=params,
            makespan=makespan,
            ranks=ranks,
            metrics=metrics,
            platform=platform,
            assignments=assignments,
            assignment_count=assignment_count,
            assignments_complete=assignments_complete,
            assignments_url=assignments_url,
            created=created,
        )

        schedule.additional_properties = d
        return schedule

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
