from typing import Literal

RTPlanKindEnum = Literal["scheduler", "whatif"]

RT_PLAN_KIND_ENUM_VALUES: set[RTPlanKindEnum] = {
    "scheduler",
    "whatif",
}


def check_rt_plan_kind_enum(value: str) -> RTPlanKindEnum:
    if value in RT_PLAN_KIND_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {RT_PLAN_KIND_ENUM_VALUES!r}")
