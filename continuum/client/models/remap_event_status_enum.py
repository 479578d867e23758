from typing import Literal

RemapEventStatusEnum = Literal["applied", "applying", "failed", "not-pushed", "what-if"]

REMAP_EVENT_STATUS_ENUM_VALUES: set[RemapEventStatusEnum] = {
    "applied",
    "applying",
    "failed",
    "not-pushed",
    "what-if",
}


def check_remap_event_status_enum(value: str) -> RemapEventStatusEnum:
    if value in REMAP_EVENT_STATUS_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {REMAP_EVENT_STATUS_ENUM_VALUES!r}")
