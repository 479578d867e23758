from typing import Literal

RemapsListDecision = Literal["partial", "total"]

REMAPS_LIST_DECISION_VALUES: set[RemapsListDecision] = {
    "partial",
    "total",
}


def check_remaps_list_decision(value: str) -> RemapsListDecision:
    if value in REMAPS_LIST_DECISION_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {REMAPS_LIST_DECISION_VALUES!r}")
