from typing import Literal

RemapsListStatus = Literal["applied", "applying", "failed", "not-pushed", "what-if"]

REMAPS_LIST_STATUS_VALUES: set[RemapsListStatus] = {
    "applied",
    "applying",
    "failed",
    "not-pushed",
    "what-if",
}


def check_remaps_list_status(value: str) -> RemapsListStatus:
    if value in REMAPS_LIST_STATUS_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {REMAPS_LIST_STATUS_VALUES!r}")
