from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast
from uuid import UUID

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.allocation_run_source_enum import AllocationRunSourceEnum, check_allocation_run_source_enum

T = TypeVar("T", bound="AllocationRun")


@_attrs_define
class AllocationRun:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        fleet (int):
        cluster (int | None):
        job (None | UUID):
        source (AllocationRunSourceEnum): * `api` - API / dashboard
            * `simulation` - Simulation
        scenario (str):
        series (None | UUID):
        t (float | None): seconds into the series
        n_monitors (int):
        n_nodes (int):
        n_topics (int):
        status (str):
        feasible (bool):
        objective (float | None): total delay of the topics received (ms)
        solve_time_ms (float | None):
        makespan_ms (float | None):
        applied (bool):
        migration_count (int):
        nodes (Any): per node: cpu, background, monitors, ...
        result (Any): the engine's Allocation.to_dict()
        created (datetime.datetime):
    """

    id: int
    fleet: int
    cluster: int | None
    job: UUID | None
    source: AllocationRunSourceEnum
    scenario: str
    series: UUID | None
    t: float | None
    n_monitors: int
    n_nodes: int
    n_topics: int
    status: str
    feasible: bool
    objective: float | None
    solve_time_ms: float | None
    makespan_ms: float | None
    applied: bool
    migration_count: int
    nodes: Any
    result: Any
    created: datetime.datetime
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        fleet = self.fleet

        cluster: int | None
        cluster = self.cluster

        job: str | None
        job = str(self.job) if isinstance(self.job, UUID) else self.job

        source: str = self.source

        scenario = self.scenario

        series: str | None
        series = str(self.series) if isinstance(self.series, UUID) else self.series

        t: float | None
        t = self.t

        n_monitors = self.n_monitors

        n_nodes = self.n_nodes

        n_topics = self.n_topics

        status = self.status

        feasible = self.feasible

        objective: float | None
        objective = self.objective

        solve_time_ms: float | None
        solve_time_ms = self.solve_time_ms

        makespan_ms: float | None
        makespan_ms = self.makespan_ms

        applied = self.applied

        migration_count = self.migration_count

        nodes = self.nodes

        result = self.result

        created = self.created.isoformat()

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "fleet": fleet,
                "cluster": cluster,
                "job": job,
                "source": source,
                "scenario": scenario,
                "series": series,
                "t": t,
                "n_monitors": n_monitors,
                "n_nodes": n_nodes,
                "n_topics": n_topics,
                "status": status,
                "feasible": feasible,
                "objective": objective,
                "solve_time_ms": solve_time_ms,
                "makespan_ms": makespan_ms,
                "applied": applied,
                "migration_count": migration_count,
                "nodes": nodes,
                "result": result,
                "created": created,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        fleet = d.pop("fleet")

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

        source = check_allocation_run_source_enum(d.pop("source"))

        scenario = d.pop("scenario")

        def _parse_series(data: object) -> UUID | None:
            if data is None:
                return data
            try:
                if not isinstance(data, str):
                    raise TypeError()
                series_type_0 = UUID(data)

                return series_type_0
            except (TypeError, ValueError, AttributeError, KeyError):
                pass
            return cast(UUID | None, data)

        series = _parse_series(d.pop("series"))

        def _parse_t(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        t = _parse_t(d.pop("t"))

        n_monitors = d.pop("n_monitors")

        n_nodes = d.pop("n_nodes")

        n_topics = d.pop("n_topics")

        status = d.pop("status")

        feasible = d.pop("feasible")

        def _parse_objective(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        objective = _parse_objective(d.pop("objective"))

        def _parse_solve_time_ms(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        solve_time_ms = _parse_solve_time_ms(d.pop("solve_time_ms"))

        def _parse_makespan_ms(data: object) -> float | None:
            if data is None:
                return data
            return cast(float | None, data)

        makespan_ms = _parse_makespan_ms(d.pop("makespan_ms"))

        applied = d.pop("applied")

        migration_count = d.pop("migration_count")

        nodes = d.pop("nodes")

        result = d.pop("result")

        created = datetime.datetime.fromisoformat(d.pop("created"))

        allocation_run = cls(
            id=id,
            fleet=fleet,
            cluster=cluster,
            job=job,
            source=source,
            scenario=scenario,
            series=series,
            t=t,
            n_monitors=n_monitors,
            n_nodes=n_nodes,
            n_topics=n_topics,
            status=status,
            feasible=feasible,
            objective=objective,
            solve_time_ms=solve_time_ms,
            makespan_ms=makespan_ms,
            applied=applied,
            migration_count=migration_count,
            nodes=nodes,
            result=result,
            created=created,
        )

        allocation_run.additional_properties = d
        return allocation_run

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
