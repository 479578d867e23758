from typing import Literal

RosgraphsListSourceFormat = Literal["autoware", "dot", "irobot", "rosgraph"]

ROSGRAPHS_LIST_SOURCE_FORMAT_VALUES: set[RosgraphsListSourceFormat] = {
    "autoware",
    "dot",
    "irobot",
    "rosgraph",
}


def check_rosgraphs_list_source_format(value: str) -> RosgraphsListSourceFormat:
    if value in ROSGRAPHS_LIST_SOURCE_FORMAT_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {ROSGRAPHS_LIST_SOURCE_FORMAT_VALUES!r}")
