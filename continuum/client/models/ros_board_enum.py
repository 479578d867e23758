from typing import Literal

RosBoardEnum = Literal["tx2", "xavier"]

ROS_BOARD_ENUM_VALUES: set[RosBoardEnum] = {
    "tx2",
    "xavier",
}


def check_ros_board_enum(value: str) -> RosBoardEnum:
    if value in ROS_BOARD_ENUM_VALUES:
        return value
    raise TypeError(f"Unexpected value {value!r}. Expected one of {ROS_BOARD_ENUM_VALUES!r}")
