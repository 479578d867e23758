from typing import Literal

ComputeNodeStatusEnum = Literal["NotReady", "Ready", "Unknown"]

COMPUTE_NODE_STATUS_ENUM_VALUES: set[ComputeNodeStatusEnum] = {
    "NotReady",
    "Ready",
    "Unknown",
}


def check_compute_node_status_enum(value: str) -> ComputeNodeStatusEnum:
    if value in COMPUTE_NODE_STATUS_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {COMPUTE_NODE_STATUS_ENUM_VALUES!r}")
