from typing import Literal

CurrentModelEnum = Literal["SC", "UM", "ZC"]

CURRENT_MODEL_ENUM_VALUES: set[CurrentModelEnum] = {
    "SC",
    "UM",
    "ZC",
}


def check_current_model_enum(value: str) -> CurrentModelEnum:
    if value in CURRENT_MODEL_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {CURRENT_MODEL_ENUM_VALUES!r}")
