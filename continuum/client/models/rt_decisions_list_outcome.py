from typing import Literal

RtDecisionsListOutcome = Literal["bound", "failed", "pending"]

RT_DECISIONS_LIST_OUTCOME_VALUES: set[RtDecisionsListOutcome] = {
    "bound",
    "failed",
    "pending",
}


def check_rt_decisions_list_outcome(value: str) -> RtDecisionsListOutcome:
    if value in RT_DECISIONS_LIST_OUTCOME_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {RT_DECISIONS_LIST_OUTCOME_VALUES!r}")
