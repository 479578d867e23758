from typing import Literal

AlgorithmEnum = Literal["gfl", "gfl_c", "heft", "heft4k", "visionworks", "visionworks_overlap", "xeft"]

ALGORITHM_ENUM_VALUES: set[AlgorithmEnum] = {
    "gfl",
    "gfl_c",
    "heft",
    "heft4k",
    "visionworks",
    "visionworks_overlap",
    "xeft",
}


def check_algorithm_enum(value: str) -> AlgorithmEnum:
    if value in ALGORITHM_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {ALGORITHM_ENUM_VALUES!r}")
