from typing import Literal

TriggerEnum = Literal["api", "watch", "what-if"]

TRIGGER_ENUM_VALUES: set[TriggerEnum] = {
    "api",
    "watch",
    "what-if",
}


def check_trigger_enum(value: str) -> TriggerEnum:
    if value in TRIGGER_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {TRIGGER_ENUM_VALUES!r}")
