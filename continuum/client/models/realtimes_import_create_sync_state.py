from typing import Literal

RealtimesImportCreateSyncState = Literal["error", "local", "synced"]

REALTIMES_IMPORT_CREATE_SYNC_STATE_VALUES: set[RealtimesImportCreateSyncState] = {
    "error",
    "local",
    "synced",
}


def check_realtimes_import_create_sync_state(value: str) -> RealtimesImportCreateSyncState:
    if value in REALTIMES_IMPORT_CREATE_SYNC_STATE_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {REALTIMES_IMPORT_CREATE_SYNC_STATE_VALUES!r}")
