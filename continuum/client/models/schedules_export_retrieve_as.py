from typing import Literal

SchedulesExportRetrieveAs = Literal["csv", "jsonl"]

SCHEDULES_EXPORT_RETRIEVE_AS_VALUES: set[SchedulesExportRetrieveAs] = {
    "csv",
    "jsonl",
}


def check_schedules_export_retrieve_as(value: str) -> SchedulesExportRetrieveAs:
    if value in SCHEDULES_EXPORT_RETRIEVE_AS_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {SCHEDULES_EXPORT_RETRIEVE_AS_VALUES!r}")
