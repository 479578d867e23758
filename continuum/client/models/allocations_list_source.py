from typing import Literal

AllocationsListSource = Literal["api", "simulation"]

ALLOCATIONS_LIST_SOURCE_VALUES: set[AllocationsListSource] = {
    "api",
    "simulation",
}


def check_allocations_list_source(value: str) -> AllocationsListSource:
    if value in ALLOCATIONS_LIST_SOURCE_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {ALLOCATIONS_LIST_SOURCE_VALUES!r}")
