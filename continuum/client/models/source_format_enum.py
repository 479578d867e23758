from typing import Literal

SourceFormatEnum = Literal["autoware", "dot", "irobot", "rosgraph"]

SOURCE_FORMAT_ENUM_VALUES: set[SourceFormatEnum] = {
    "autoware",
    "dot",
    "irobot",
    "rosgraph",
}


def check_source_format_enum(value: str) -> SourceFormatEnum:
    if value in SOURCE_FORMAT_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {SOURCE_FORMAT_ENUM_VALUES!r}")
