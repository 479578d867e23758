from typing import Literal

AllocationRunSourceEnum = Literal["api", "simulation"]

ALLOCATION_RUN_SOURCE_ENUM_VALUES: set[AllocationRunSourceEnum] = {
    "api",
    "simulation",
}


def check_allocation_run_source_enum(value: str) -> AllocationRunSourceEnum:
    if value in ALLOCATION_RUN_SOURCE_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {ALLOCATION_RUN_SOURCE_ENUM_VALUES!r}")
