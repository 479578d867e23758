from typing import Literal

EvictionPolicyEnum = Literal["linear", "linearithmic", "quadratic"]

EVICTION_POLICY_ENUM_VALUES: set[EvictionPolicyEnum] = {
    "linear",
    "linearithmic",
    "quadratic",
}


def check_eviction_policy_enum(value: str) -> EvictionPolicyEnum:
    if value in EVICTION_POLICY_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {EVICTION_POLICY_ENUM_VALUES!r}")
