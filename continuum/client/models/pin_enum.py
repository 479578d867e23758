from typing import Literal

PinEnum = Literal["free", "robot"]

PIN_ENUM_VALUES: set[PinEnum] = {
    "free",
    "robot",
}


def check_pin_enum(value: str) -> PinEnum:
    if value in PIN_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {PIN_ENUM_VALUES!r}")
