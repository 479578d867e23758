from typing import Literal

RankModeEnum = Literal["max", "mean"]

RANK_MODE_ENUM_VALUES: set[RankModeEnum] = {
    "max",
    "mean",
}


def check_rank_mode_enum(value: str) -> RankModeEnum:
    if value in RANK_MODE_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {RANK_MODE_ENUM_VALUES!r}")
