from typing import Literal

CommModeEnum = Literal["impl", "pairs"]

COMM_MODE_ENUM_VALUES: set[CommModeEnum] = {
    "impl",
    "pairs",
}


def check_comm_mode_enum(value: str) -> CommModeEnum:
    if value in COMM_MODE_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {COMM_MODE_ENUM_VALUES!r}")
