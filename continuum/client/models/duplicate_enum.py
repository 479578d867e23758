from typing import Literal

DuplicateEnum = Literal["allow", "refuse"]

DUPLICATE_ENUM_VALUES: set[DuplicateEnum] = {
    "allow",
    "refuse",
}


def check_duplicate_enum(value: str) -> DuplicateEnum:
    if value in DUPLICATE_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {DUPLICATE_ENUM_VALUES!r}")
