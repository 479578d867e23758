"""Fixtures of the fleet client's tests: rosbag2 recordings written with ``rosbags`` and a live server."""

from __future__ import annotations

from pathlib import Path

import pytest

T0 = 1_700_000_000_000_000_000  # ns: the recordings' first message


def write_bag(
    path: Path, storage: str, topics: dict[str, tuple[str, float, int, object]], compression: str | None = None
) -> Path:
    """A rosbag2 recording: per topic (msgtype, rate_hz, count, make(i) -> message), evenly spaced from T0.
    ``compression``: None, "file" or "message" (zstd, rosbag2's modes) or "storage" (MCAP's zstd chunks)."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.rosbag2.enums import CompressionFormat, CompressionMode
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    plugin = {"sqlite3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}[storage]
    w = Writer(path, version=9, storage_plugin=plugin)
    if compression:
        w.set_compression(CompressionMode[compression.upper()], CompressionFormat.ZSTD)
    with w:
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


def write_bag1(
    path: Path,
    topics: dict[str, tuple[str, float, int, object]],
    compression: str | None = None,
    callerid: str = "/talker",
) -> Path:
    """A rosbag1 recording (``rosbags``' writer, ROS 1 Noetic types), like :func:`write_bag`; ``compression``
    None, "bz2" or "lz4" (rosbag1's chunk compressions)."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    w = Writer(path)
    if compression:
        w.set_compression(Writer.CompressionFormat[compression.upper()])
    with w:
        rows = []
        for topic, (msgtype, rate, count, make) in topics.items():
            conn = w.add_connection(topic, msgtype, typestore=store, callerid=callerid)
            rows += [(T0 + round(i * 1e9 / rate), conn, msgtype, make(store.types[msgtype], i)) for i in range(count)]
        for stamp, conn, msgtype, msg in sorted(rows, key=lambda r: r[0]):
            w.write(conn, stamp, store.serialize_ros1(msg, msgtype))
    return path


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
