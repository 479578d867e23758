from typing import Literal

MonitorsListVerdict = Literal["fail", "inconclusive", "pass", "pending"]

MONITORS_LIST_VERDICT_VALUES: set[MonitorsListVerdict] = {
    "fail",
    "inconclusive",
    "pass",
    "pending",
}


def check_monitors_list_verdict(value: str) -> MonitorsListVerdict:
    if value in MONITORS_LIST_VERDICT_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {MONITORS_LIST_VERDICT_VALUES!r}")
