from typing import Literal

RtEventsListKind = Literal["alert", "eviction"]

RT_EVENTS_LIST_KIND_VALUES: set[RtEventsListKind] = {
    "alert",
    "eviction",
}


def check_rt_events_list_kind(value: str) -> RtEventsListKind:
    if value in RT_EVENTS_LIST_KIND_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {RT_EVENTS_LIST_KIND_VALUES!r}")
