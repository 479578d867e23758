from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, TypeVar

from attrs import define as _attrs_define
from attrs import field as _attrs_field

from ..types import UNSET, Unset

if TYPE_CHECKING:
    from ..models.report_batch_request_reports_item import ReportBatchRequestReportsItem


T = TypeVar("T", bound="ReportBatchRequest")


@_attrs_define
class ReportBatchRequest:
    """For the API docs only: the endpoint reads the body itself (it must be fast).

    Attributes:
        reports (list[ReportBatchRequestReportsItem]): Monitoring objects (Listing 3.37) or their spec: node,
            containerName, missedDeadlinesPeriod, missedDeadlinesTotal; optional pod, sentAt and missAt (RFC 3339 or epoch
            seconds) and report_id (or id: the report's idempotency key, unique per cluster; default: a digest of the
            report's content). A report whose id was seen before is acknowledged as a duplicate and not acted on again.
        cluster (int | Unset): default: the fleet's only cluster
    """

    reports: list[ReportBatchRequestReportsItem]
    cluster: int | Unset = UNSET
    additional_properties: dict[str, Any] = _attrs_field(init=False, factory=dict)

    def to_dict(self) -> dict[str, Any]:
        reports = []
        for reports_item_data in self.reports:
            reports_item = reports_item_data.to_dict()
            reports.append(reports_item)

        cluster = self.cluster

        field_dict: dict[str, Any] = {}
        field_dict.update(self.additional_properties)
        field_dict.update(
            {
                "reports": reports,
            }
        )
        if cluster is not UNSET:
            field_dict["cluster"] = cluster

        return field_dict

    @classmethod
    def from_dict(cls: type[T], src_dict: Mapping[str, Any]) -> T:
        from ..models.report_batch_request_reports_item import ReportBatchRequestReportsItem

        d = dict(src_dict)
        reports = []
        _reports = d.pop("reports")
        for reports_item_data in _reports:
            reports_item = ReportBatchRequestReportsItem.from_dict(reports_item_data)

            reports.append(reports_item)

        cluster = d.pop("cluster", UNSET)

        report_batch_request = cls(
            reports=reports,
            cluster=cluster,
        )

        report_batch_request.additional_properties = d
        return report_batch_request

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
