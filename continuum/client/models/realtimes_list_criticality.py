from typing import Literal

RealtimesListCriticality = Literal["A", "B", "C", "D"]

REALTIMES_LIST_CRITICALITY_VALUES: set[RealtimesListCriticality] = {
    "A",
    "B",
    "C",
    "D",
}


def check_realtimes_list_criticality(value: str) -> RealtimesListCriticality:
    if value in REALTIMES_LIST_CRITICALITY_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {REALTIMES_LIST_CRITICALITY_VALUES!r}")
