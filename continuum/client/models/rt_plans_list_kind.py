from typing import Literal

RtPlansListKind = Literal["scheduler", "whatif"]

RT_PLANS_LIST_KIND_VALUES: set[RtPlansListKind] = {
    "scheduler",
    "whatif",
}


def check_rt_plans_list_kind(value: str) -> RtPlansListKind:
    if value in RT_PLANS_LIST_KIND_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {RT_PLANS_LIST_KIND_VALUES!r}")
