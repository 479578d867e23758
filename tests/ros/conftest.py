"""Fixtures of the live ROS tests: a real roscore per test (Debian's ROS 1)."""

from __future__ import annotations

import pytest

from .ros1 import roscore


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "ros: needs Debian's ROS 1 (roscore, rospy, rosbag: scripts/services.sh ensure_ros1)"
    )


@pytest.fixture
def ros1(tmp_path):
    with roscore(tmp_path / "ros") as ros:
        yield ros
