from typing import Literal

LinearResourceEnum = Literal["cpu", "memory"]

LINEAR_RESOURCE_ENUM_VALUES: set[LinearResourceEnum] = {
    "cpu",
    "memory",
}


def check_linear_resource_enum(value: str) -> LinearResourceEnum:
    if value in LINEAR_RESOURCE_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {LINEAR_RESOURCE_ENUM_VALUES!r}")
