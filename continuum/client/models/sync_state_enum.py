from typing import Literal

SyncStateEnum = Literal["error", "local", "synced"]

SYNC_STATE_ENUM_VALUES: set[SyncStateEnum] = {
    "error",
    "local",
    "synced",
}


def check_sync_state_enum(value: str) -> SyncStateEnum:
    if value in SYNC_STATE_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {SYNC_STATE_ENUM_VALUES!r}")
