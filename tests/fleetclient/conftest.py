"""Fixtures of the fleet client's tests: rosbag2 recordings written with ``rosbags`` and a live server."""

from __future__ import annotations

from pathlib import Path

import pytest

T0 = 1_700_000_000_000_000_000  # ns: the recordings' first message


def write_bag(path: Path, storage: str, topics: dict[str, tuple[str, float, int, object]]) -> Path:
    """A rosbag2 recording: per topic (msgtype, rate_hz, count, make(i) -> message), evenly spaced from T0."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    plugin = {"sqlite3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}[storage]
    with Writer(path, version=9, storage_plugin=plugin) as w:
        rows = []
        for topic, (msgtype, rate, count, make) in topics.items():
            conn = w.add_connection(topic, msgtype, typestore=store)
            rows += [(T0 + round(i * 1e9 / rate), conn, msgtype, make(store.types[msgtype], i)) for i in range(count)]
        for stamp, conn, msgtype, msg in sorted(rows, key=lambda r: r[0]):
            w.write(conn, stamp, store.serialize_cdr(msg, msgtype))
    return path


def robot_topics() -> dict:
    """A robot's run: /scan-like strings at 10 Hz, speed at 20 Hz, arrival once at the end (1 s)."""

    def header(types, i):
        return types(data=f"scan {i:03d} " + "x" * 100)

    return {
        "/scan": ("std_msgs/msg/String", 10.0, 11, header),
        "/speed": ("std_msgs/msg/Float64", 20.0, 21, lambda t, i: t(data=0.5 * i)),
        "/arrived": ("std_msgs/msg/Bool", 1.0, 2, lambda t, i: t(data=bool(i))),
    }


@pytest.fixture(params=["sqlite3", "mcap"])
def robot_bag(request, tmp_path) -> Path:
    return write_bag(tmp_path / f"run-{request.param}", request.param, robot_topics())


@pytest.fixture
def token(fleet_token) -> str:
    # Tokens are stored hashed: the fixture keeps the one-time plaintext key.
    return fleet_token.plaintext


@pytest.fixture
def fleet_client(live_server, token):
    from continuum.fleet import Fleet

    with Fleet(live_server.url, token, timeout=30, retries=1, backoff=0.05) as client:
        yield client
