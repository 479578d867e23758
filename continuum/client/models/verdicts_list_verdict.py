from typing import Literal

VerdictsListVerdict = Literal["fail", "inconclusive", "pass", "pending"]

VERDICTS_LIST_VERDICT_VALUES: set[VerdictsListVerdict] = {
    "fail",
    "inconclusive",
    "pass",
    "pending",
}


def check_verdicts_list_verdict(value: str) -> VerdictsListVerdict:
    if value in VERDICTS_LIST_VERDICT_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {VERDICTS_LIST_VERDICT_VALUES!r}")
