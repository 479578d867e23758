from typing import Literal

ScenarioEnum = Literal["kairos", "synthetic"]

SCENARIO_ENUM_VALUES: set[ScenarioEnum] = {
    "kairos",
    "synthetic",
}


def check_scenario_enum(value: str) -> ScenarioEnum:
    if value in SCENARIO_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {SCENARIO_ENUM_VALUES!r}")
