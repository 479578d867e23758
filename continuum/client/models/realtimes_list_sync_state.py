from typing import Literal

RealtimesListSyncState = Literal["error", "local", "synced"]

REALTIMES_LIST_SYNC_STATE_VALUES: set[RealtimesListSyncState] = {
    "error",
    "local",
    "synced",
}


def check_realtimes_list_sync_state(value: str) -> RealtimesListSyncState:
    if value in REALTIMES_LIST_SYNC_STATE_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {REALTIMES_LIST_SYNC_STATE_VALUES!r}")
