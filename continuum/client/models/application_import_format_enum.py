from typing import Literal

ApplicationImportFormatEnum = Literal["continuum", "dax", "stg", "thesis_csv", "wfformat"]

APPLICATION_IMPORT_FORMAT_ENUM_VALUES: set[ApplicationImportFormatEnum] = {
    "continuum",
    "dax",
    "stg",
    "thesis_csv",
    "wfformat",
}


def check_application_import_format_enum(value: str) -> ApplicationImportFormatEnum:
    if value in APPLICATION_IMPORT_FORMAT_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {APPLICATION_IMPORT_FORMAT_ENUM_VALUES!r}")
