from __future__ import annotations

import datetime
from collections.abc import Mapping
from typing import Any, TypeVar, cast

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..models.monitoring_report_source_enum import MonitoringReportSourceEnum, check_monitoring_report_source_enum

T = TypeVar("T", bound="MonitoringReport")


@_attrs_define
class MonitoringReport:
    """The base of every model serializer of the API.

    Attributes:
        id (int):
        cluster (int):
        name (str):
        node (str):
        container_name (str):
        pod (str):
        missed_period (int):
        missed_total (int):
        violation (str): period or total when over the threshold
        miss_at (datetime.datetime | None): the miss that crossed the threshold (monitor)
        sent_at (datetime.datetime | None): when the monitor sent it (its clock)
        received_at (datetime.datetime):
        source (MonitoringReportSourceEnum): * `rest` - Rest
            * `kube` - custom object
        report_id (None | str):
        startup_overruns (int):
    """

    id: int
    cluster: int
    name: str
    node: str
    container_name: str
    pod: str
    missed_period: int
    missed_total: int
    violation: str
    miss_at: datetime.datetime | None
    sent_at: datetime.datetime | None
    received_at: datetime.datetime
    source: MonitoringReportSourceEnum
    report_id: str | None
    startup_overruns: int
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        id = self.id

        cluster = self.cluster

        name = self.name

        node = self.node

        container_name = self.container_name

        pod = self.pod

        missed_period = self.missed_period

        missed_total = self.missed_total

        violation = self.violation

        miss_at: str | None
        miss_at = self.miss_at.isoformat() if isinstance(self.miss_at, datetime.datetime) else self.miss_at

        sent_at: str | None
        sent_at = self.sent_at.isoformat() if isinstance(self.sent_at, datetime.datetime) else self.sent_at

        received_at = self.received_at.isoformat()

        source: str = self.source

        report_id: str | None
        report_id = self.report_id

        startup_overruns = self.startup_overruns

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "id": id,
                "cluster": cluster,
                "name": name,
                "node": node,
                "container_name": container_name,
                "pod": pod,
                "missed_period": missed_period,
                "missed_total": missed_total,
                "violation": violation,
                "miss_at": miss_at,
                "sent_at": sent_at,
                "received_at": received_at,
                "source": source,
                "report_id": report_id,
                "startup_overruns": startup_overruns,
            }
        )

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        d = dict(src_dict)
        id = d.pop("id")

        cluster = d.pop("cluster")

        name = d.pop("name")

        node = d.pop("node")

        container_name = d.pop("container_name")

        pod = d.pop("pod")

        missed_period = d.pop("missed_period")

        missed_total = d.pop("missed_total")

        violation = d.pop("violation")

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

        source = check_monitoring_report_source_enum(d.pop("source"))

        def _parse_report_id(data: object) -> str | None:
            if data is None:
                return data
            return cast(str | None, data)

        report_id = _parse_report_id(d.pop("report_id"))

        startup_overruns = d.pop("startup_overruns")

        monitoring_report = cls(
            id=id,
            cluster=cluster,
            name=name,
            node=node,
            container_name=container_name,
            pod=pod,
            missed_period=missed_period,
            missed_total=missed_total,
            violation=violation,
            miss_at=miss_at,
            sent_at=sent_at,
            received_at=received_at,
            source=source,
            report_id=report_id,
            startup_overruns=startup_overruns,
        )

        monitoring_report.additional_properties = d
        return monitoring_report

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
