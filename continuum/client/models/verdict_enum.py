from typing import Literal

VerdictEnum = Literal["fail", "inconclusive", "pass", "pending"]

VERDICT_ENUM_VALUES: set[VerdictEnum] = {
    "fail",
    "inconclusive",
    "pass",
    "pending",
}


def check_verdict_enum(value: str) -> VerdictEnum:
    if value in VERDICT_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {VERDICT_ENUM_VALUES!r}")
