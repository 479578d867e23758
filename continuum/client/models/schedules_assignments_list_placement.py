from typing import Literal

SchedulesAssignmentsListPlacement = Literal["bound", "failed", "not_pushed"]

SCHEDULES_ASSIGNMENTS_LIST_PLACEMENT_VALUES: set[SchedulesAssignmentsListPlacement] = {
    "bound",
    "failed",
    "not_pushed",
}


def check_schedules_assignments_list_placement(value: str) -> SchedulesAssignmentsListPlacement:
    if value in SCHEDULES_ASSIGNMENTS_LIST_PLACEMENT_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {SCHEDULES_ASSIGNMENTS_LIST_PLACEMENT_VALUES!r}")
