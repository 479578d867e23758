from typing import Literal

RTEventKindEnum = Literal["alert", "eviction"]

RT_EVENT_KIND_ENUM_VALUES: set[RTEventKindEnum] = {
    "alert",
    "eviction",
}


def check_rt_event_kind_enum(value: str) -> RTEventKindEnum:
    if value in RT_EVENT_KIND_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {RT_EVENT_KIND_ENUM_VALUES!r}")
