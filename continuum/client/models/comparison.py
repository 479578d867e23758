from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar, cast
from uuid import UUID

from attrs import define as _attrs_define
from attrs import field as _attrs_field

if TYPE_CHECKING:
    from ..models.comparison_figures import ComparisonFigures
    from ..models.comparison_relative import ComparisonRelative
    from ..models.comparison_schedules_item import ComparisonSchedulesItem


T = TypeVar("T", bound="Comparison")


@_attrs_define
class Comparison:
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
            reference_makespan (float | None):
            figures (ComparisonFigures):
            relative (ComparisonRelative):
            schedules (list[ComparisonSchedulesItem]):
            platform (Any): the platform compared on, as continuum.platform/v1
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
    reference_makespan: float | None
    figures: ComparisonFigures
    relative: ComparisonRelative
    schedules: list[ComparisonSchedulesItem]
    platform: Any
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

        reference_makespan: float | None
        reference_makespan = self.reference_makespan

        figures = self.figures.to_dict()

        relative = self.relative.to_dict()

        schedules = []
        for schedules_item_data in self.schedules:
            schedules_item = schedules_item_data.to_dict()
            schedules.append(schedules_item)

        platform = self.platform

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
                "reference_makespan": reference_makespan,
                "figures": figures,
                "relative": relative,
                "schedules": schedules,
                "platform": platform,
                "created": created,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.comparison_figures import ComparisonFigures
        from ..models.comparison_relative import ComparisonRelative
        from ..models.comparison_schedules_item import ComparisonSchedulesItem

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

        def _parse_reference_makespan(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        reference_makespan = _parse_reference_makespan(d.pop("reference_makespan"))

        figures = ComparisonFigures.from_dict(d.pop("figures"))

        relative = ComparisonRelative.from_dict(d.pop("relative"))

        schedules = []
        _schedules = d.pop("schedules")
        for schedules_item_data in _schedules:
            schedules_item = ComparisonSchedulesItem.from_dict(schedules_item_data)

            schedules.append(schedules_item)

        platform = d.pop("platform")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        comparison = cls(
            id=id,
            fleet=fleet,
            application=application,
            cluster=cluster,
            job=job,
            algorithms=algorithms,
            params=params,
            best=best,
            reference_makespan=reference_makespan,
            figures=figures,
            relative=relative,
            schedules=schedules,
            platform=platform,
            created=created,
        )

        comparison.additional_properties = d
        return comparison

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
