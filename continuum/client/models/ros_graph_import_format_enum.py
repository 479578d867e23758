from typing import Literal

RosGraphImportFormatEnum = Literal["autoware", "dot", "irobot", "rosgraph"]

ROS_GRAPH_IMPORT_FORMAT_ENUM_VALUES: set[RosGraphImportFormatEnum] = {
    "autoware",
    "dot",
    "irobot",
    "rosgraph",
}


def check_ros_graph_import_format_enum(value: str) -> RosGraphImportFormatEnum:
    if value in ROS_GRAPH_IMPORT_FORMAT_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {ROS_GRAPH_IMPORT_FORMAT_ENUM_VALUES!r}")
