"""Fixtures of the live ROS tests: a real roscore per test (Debian's ROS 1)."""

from __future__ import annotations

import pytest

from .ros1 import roscore


@pytest.fixture
def ros1(tmp_path):
    with roscore(tmp_path / "ros") as ros:
        yield ros
