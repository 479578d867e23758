from typing import Literal

RemapsListTrigger = Literal["api", "watch", "what-if"]

REMAPS_LIST_TRIGGER_VALUES: set[RemapsListTrigger] = {
    "api",
    "watch",
    "what-if",
}


def check_remaps_list_trigger(value: str) -> RemapsListTrigger:
    if value in REMAPS_LIST_TRIGGER_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {REMAPS_LIST_TRIGGER_VALUES!r}")
