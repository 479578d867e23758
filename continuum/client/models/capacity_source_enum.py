from typing import Literal

CapacitySourceEnum = Literal["declared", "reported"]

CAPACITY_SOURCE_ENUM_VALUES: set[CapacitySourceEnum] = {
    "declared",
    "reported",
}


def check_capacity_source_enum(value: str) -> CapacitySourceEnum:
    if value in CAPACITY_SOURCE_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {CAPACITY_SOURCE_ENUM_VALUES!r}")
