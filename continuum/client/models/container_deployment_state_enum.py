from typing import Literal

ContainerDeploymentStateEnum = Literal["applied", "failed", "not_pushed", "superseded"]

CONTAINER_DEPLOYMENT_STATE_ENUM_VALUES: set[ContainerDeploymentStateEnum] = {
    "applied",
    "failed",
    "not_pushed",
    "superseded",
}


def check_container_deployment_state_enum(value: str) -> ContainerDeploymentStateEnum:
    if value in CONTAINER_DEPLOYMENT_STATE_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {CONTAINER_DEPLOYMENT_STATE_ENUM_VALUES!r}")
