from typing import Literal

PolicyEnum = Literal["default", "default-kubernetes", "k8s", "kubernetes", "superclustering"]

POLICY_ENUM_VALUES: set[PolicyEnum] = {
    "default",
    "default-kubernetes",
    "k8s",
    "kubernetes",
    "superclustering",
}


def check_policy_enum(value: str) -> PolicyEnum:
    if value in POLICY_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {POLICY_ENUM_VALUES!r}")
