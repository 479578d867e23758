from typing import Literal

SortTiebreakEnum = Literal["arrival", "utilization"]

SORT_TIEBREAK_ENUM_VALUES: set[SortTiebreakEnum] = {
    "arrival",
    "utilization",
}


def check_sort_tiebreak_enum(value: str) -> SortTiebreakEnum:
    if value in SORT_TIEBREAK_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {SORT_TIEBREAK_ENUM_VALUES!r}")
