from typing import Literal

BScoreArgumentEnum = Literal["free", "load"]

B_SCORE_ARGUMENT_ENUM_VALUES: set[BScoreArgumentEnum] = {
    "free",
    "load",
}


def check_b_score_argument_enum(value: str) -> BScoreArgumentEnum:
    if value in B_SCORE_ARGUMENT_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {B_SCORE_ARGUMENT_ENUM_VALUES!r}")
