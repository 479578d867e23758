from typing import Literal

RealtimesImportCreateCriticality = Literal["A", "B", "C", "D"]

REALTIMES_IMPORT_CREATE_CRITICALITY_VALUES: set[RealtimesImportCreateCriticality] = {
    "A",
    "B",
    "C",
    "D",
}


def check_realtimes_import_create_criticality(value: str) -> RealtimesImportCreateCriticality:
    if value in REALTIMES_IMPORT_CREATE_CRITICALITY_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {REALTIMES_IMPORT_CREATE_CRITICALITY_VALUES!r}")
