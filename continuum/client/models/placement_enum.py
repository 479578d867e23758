from typing import Literal

PlacementEnum = Literal["bound", "failed", "not_pushed"]

PLACEMENT_ENUM_VALUES: set[PlacementEnum] = {
    "bound",
    "failed",
    "not_pushed",
}


def check_placement_enum(value: str) -> PlacementEnum:
    if value in PLACEMENT_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {PLACEMENT_ENUM_VALUES!r}")
