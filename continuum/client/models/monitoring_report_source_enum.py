from typing import Literal

MonitoringReportSourceEnum = Literal["kube", "rest"]

MONITORING_REPORT_SOURCE_ENUM_VALUES: set[MonitoringReportSourceEnum] = {
    "kube",
    "rest",
}


def check_monitoring_report_source_enum(value: str) -> MonitoringReportSourceEnum:
    if value in MONITORING_REPORT_SOURCE_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {MONITORING_REPORT_SOURCE_ENUM_VALUES!r}")
