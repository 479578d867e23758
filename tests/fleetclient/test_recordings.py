"""Every kind of recording the fleet client reads, with ``rosbags``: ros2/rosbag2's own published test bags, rosbag2
written here in each compression mode, rosbag1 in each chunk compression, a bag with service events, and the
bounds that keep a hostile recording from exhausting memory or the stack. (Recordings made by Debian's ROS 1
``rosbag record`` are in tests/ros/test_rosbag_record.py.)"""

from __future__ import annotations

import contextlib
import io
import shutil
from pathlib import Path

import pytest
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

from continuum.fleet import bags
from continuum.fleet.cli import main
from continuum.fleet.rosbag import BagError, describe_bag, events_from_bag, read_stats, rosgraph_from_bag

from .conftest import robot_topics, write_bag, write_bag1

PUBLISHED = Path(__file__).resolve().parents[1] / "data" / "rosbag2"


def run(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


# ---- ros2/rosbag2's own recordings -------------------------------------------------------------------------
@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_published_talker_bags_report_their_messages(storage):
    bag = PUBLISHED / storage / "talker"
    stats = read_stats(bag)
    # metadata.yaml and the storage disagree on the QoS profiles: the storage's topics are the truth
    assert {t: s.messages for t, s in stats.topics.items()} == {"/topic": 10, "/rosout": 10, "/parameter_events": 0}
    assert stats.topics["/topic"].mean_bytes == 24.0  # "Hello, world! N" in CDR: 4 header + 4 length + 16
    assert stats.rate_hz("/topic") == pytest.approx(2.0, rel=0.01)  # the demo talker publishes at 2 Hz
    info = {t["name"]: t for t in describe_bag(bag)["topics"]}
    assert info["/topic"]["decodable"] and info["/rosout"]["decodable"]
    levels = [e for e in events_from_bag(bag) if e[0] == "rosout.level"]
    assert [e[1] for e in levels] == [20] * 10  # INFO; the type's constants (DEBUG=10, ...) are not signals
    assert not any(e[0] == "rosout.DEBUG" for e in events_from_bag(bag))
    doc = rosgraph_from_bag(bag)
    assert doc["meta"]["messages"] == {"/parameter_events": 0, "/rosout": 10, "/topic": 10}


def test_published_bag_with_definitions_decodes_test_types():
    events = list(events_from_bag(PUBLISHED / "mcap" / "convert_a"))  # its MCAP schemas define test_msgs
    assert {e[0] for e in events} >= {"b_basictypes.int64_value", "b_basictypes.bool_value"}


def test_published_bag_without_definitions_says_so_in_one_line_per_topic():
    bag = PUBLISHED / "sqlite3" / "convert_a"
    assert {t: s.messages for t, s in read_stats(bag).topics.items()} == {"a_empty": 100, "b_basictypes": 50}
    code, out, err = run("bag-events", "--dry-run", str(bag))
    assert code == 0 and out == ""
    assert err.splitlines() == [
        "warning: a_empty (test_msgs/msg/Empty) skipped: "
        "test_msgs/msg/Empty: no definition in the recording and none in ROS 2 Humble",
        "warning: b_basictypes (test_msgs/msg/BasicTypes) skipped: "
        "test_msgs/msg/BasicTypes: no definition in the recording and none in ROS 2 Humble",
    ]
    code, out, err = run("bag-events", "--dry-run", "--topic", "b_basictypes", str(bag))
    assert code == 2 and len(err.splitlines()) == 1 and "cannot decode b_basictypes" in err


# ---- service events ----------------------------------------------------------------------------------------
def service_event_bag(path: Path) -> Path:
    """What ``ros2 bag record --all-services`` leaves for a type rosbags cannot parse: the event topic's schema
    is the ``.srv`` text. A plain topic beside it must still decode."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        event = w.add_connection("/add_two_ints/_service_event", "example_interfaces/srv/AddTwoInts_Event",
                                 msgdef="int64 a\nint64 b\n---\nint64 sum\n", rihs01="RIHS01_" + "0" * 64)  # fmt: skip
        chatter = w.add_connection("/chatter", "std_msgs/msg/String", typestore=store)
        for i in range(3):
            w.write(event, 10 + i, b"\x00\x01\x00\x00" + bytes(40))
            w.write(chatter, 11 + i, store.serialize_cdr(store.types["std_msgs/msg/String"](data=f"hi {i}"),
                                                         "std_msgs/msg/String"))  # fmt: skip
    return path


def test_service_events_are_one_line_and_the_rest_decodes(tmp_path):
    bag = service_event_bag(tmp_path / "services")
    code, out, err = run("bag-info", str(bag))
    assert code == 0 and err == ""
    line = next(x for x in out.splitlines() if "(example_interfaces" in x)
    assert "3 messages" in line and "not decodable: cannot read the recording's service event type" in line
    assert "/chatter (std_msgs/msg/String): 3 messages" in out and out.count("; decodable") == 1
    code, out, err = run("bag-events", "--dry-run", str(bag))
    assert code == 0 and len(err.splitlines()) == 1 and err.startswith("warning: /add_two_ints/_service_event")
    assert read_stats(bag).topics["/add_two_ints/_service_event"].messages == 3


# ---- rosbag2 in every compression mode, rosbag1 in every chunk compression ---------------------------------
def expected_events(bag) -> list:
    return [e for e in events_from_bag(bag) if e[0] in ("speed.data", "arrived.data")]


@pytest.mark.parametrize(("storage", "compression"),
                         [("sqlite3", "file"), ("sqlite3", "message"), ("mcap", "file"), ("mcap", "message"),
                          ("mcap", "storage")])  # fmt: skip
def test_rosbag2_compressed_reads_like_uncompressed(tmp_path, storage, compression):
    plain = write_bag(tmp_path / "plain", storage, robot_topics())
    packed = write_bag(tmp_path / "packed", storage, robot_topics(), compression=compression)
    a, b = read_stats(plain), read_stats(packed)
    assert {t: (s.messages, s.total_bytes) for t, s in a.topics.items()} == {
        t: (s.messages, s.total_bytes) for t, s in b.topics.items()
    }
    assert expected_events(packed) == expected_events(plain) and len(expected_events(plain)) == 23


@pytest.mark.parametrize("compression", [None, "bz2", "lz4"])
def test_rosbag1_with_publishers_from_callerid(tmp_path, compression):
    topics = {
        "/speed": ("std_msgs/msg/Float64", 20.0, 21, lambda t, i: t(data=0.5 * i)),
        "/scan": ("std_msgs/msg/String", 10.0, 11, lambda t, i: t(data="x" * 96)),
    }
    bag = write_bag1(tmp_path / "run.bag", topics, compression=compression, callerid="/lidar_driver")
    stats = read_stats(bag)
    assert stats.kind == "rosbag1"
    assert round(stats.rate_hz("/speed"), 6) == 20.0 and round(stats.rate_hz("/scan"), 6) == 10.0
    assert stats.topics["/scan"].mean_bytes == 100.0  # ROS 1 serialization: 4 bytes of length + 96
    doc = rosgraph_from_bag(bag)
    assert {t["name"]: t["publishers"] for t in doc["topics"]} == {
        "/scan": ["/lidar_driver"],
        "/speed": ["/lidar_driver"],
    }
    assert doc["meta"]["source"] == "rosbag1" and doc["meta"]["unnamed_publishers"] == []
    speed = [e for e in events_from_bag(bag) if e[0] == "speed.data"]
    assert speed == [["speed.data", 0.5 * i, i * 50.0] for i in range(21)]


def test_single_storage_files_are_recordings_too(tmp_path):
    for storage, suffix in (("sqlite3", ".db3"), ("mcap", ".mcap")):
        bag = write_bag(tmp_path / storage, storage, robot_topics())
        (file,) = bag.glob(f"*{suffix}")
        assert read_stats(file).topics["/speed"].messages == 21


# ---- bounds ------------------------------------------------------------------------------------------------
def zstd_bomb(size: int) -> bytes:
    """A zstd frame of ``size`` zero bytes (a few kilobytes per gigabyte), made without holding them."""
    c = bags.zstd.ZstdCompressor()
    block = bytes(1 << 20)
    return b"".join(c.compress(block) for _ in range(size >> 20)) + c.flush()


def test_a_message_bomb_stops_at_the_limit(tmp_path):
    """A 3 GiB zstd message (the size of issue 25's) is refused after MAX_INFLATE bytes, with the default limit."""
    bag = write_bag(tmp_path / "bomb", "sqlite3", {"/speed": ("std_msgs/msg/Float64", 10.0, 2, lambda t, i: t(data=i))})
    bomb = zstd_bomb(3 << 30)
    assert len(bomb) < 200_000
    import sqlite3

    (db,) = bag.glob("*.db3")
    with sqlite3.connect(db) as con:
        con.execute("UPDATE messages SET data = ?", (bomb,))
    meta = bag / "metadata.yaml"
    meta.write_text(meta.read_text().replace("compression_mode: ''", "compression_mode: message").replace(
        "compression_format: ''", "compression_format: zstd"))  # fmt: skip
    code, _, err = run("bag-graph", str(bag))
    assert code == 2 and err.count("\n") == 1
    assert f"inflates to more than {bags.MAX_INFLATE // 2**20} MiB" in err


def test_a_file_bomb_stops_at_the_limit(tmp_path, monkeypatch):
    monkeypatch.setattr(bags, "MAX_FILE_INFLATE", 64 << 20)
    bag = write_bag(tmp_path / "fbomb", "mcap", robot_topics(), compression="file")
    (packed,) = bag.glob("*.zstd")
    packed.write_bytes(zstd_bomb(65 << 20))
    with pytest.raises(BagError, match="inflates to more than 64 MiB"):
        read_stats(bag)
    assert not list(Path(bags.tempfile.gettempdir()).glob("continuum-bag-*/" + packed.stem))  # cleaned up


def test_chunk_bounds(tmp_path, monkeypatch):
    monkeypatch.setattr(bags, "MAX_INFLATE", 512)
    bag = write_bag(tmp_path / "chunks", "mcap", robot_topics(), compression="storage")
    with pytest.raises(BagError, match=r"an MCAP chunk declares .* bytes inflated, more than"):
        read_stats(bag)
    # a chunk that inflates to more than it declares stops there
    monkeypatch.setattr(bags, "MAX_INFLATE", 1 << 20)
    with pytest.raises(BagError, match="inflates to more than"):
        bags._mcap.DECOMPRESSORS["zstd"](zstd_bomb(1 << 20), 1000)
    with pytest.raises(BagError, match="a rosbag1 chunk inflates to more than 1 MiB"):
        bags._rosbag1_reader.decompressors["lz4"](bags.lz4.frame.compress(bytes(2 << 20)))
    monkeypatch.setattr(bags, "MAX_INFLATE", 512)
    big = {"/scan": ("std_msgs/msg/String", 10.0, 20, lambda t, i: t(data="x" * 1000))}
    with pytest.raises(BagError, match="a rosbag1 chunk inflates to more than"):
        read_stats(write_bag1(tmp_path / "big.bag", big, compression="bz2"))


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        ("rosbag2_bagfile_information: " + "[" * 100_000 + "]" * 100_000, "nested deeper than 32 levels"),
        ("a:\n" + "".join(" " * (i + 1) + f"k{i}:\n" for i in range(600)), "nested deeper than 32 levels"),
        ("a: &x [1]\nb: [" + ", ".join(["*x"] * 200) + "]\n", "more than 100 YAML aliases"),
        ("version: 1\n", "no rosbag2_bagfile_information"),
        ("rosbag2_bagfile_information: {version: 99}", "metadata version 99"),
        ("rosbag2_bagfile_information: {version: 5, storage_identifier: sqlite3, relative_file_paths: "
         "['../../etc/passwd']}", "storage file 'passwd' is missing"),
    ],
)  # fmt: skip
def test_hostile_metadata_is_one_line(tmp_path, text, problem):
    (tmp_path / "bag").mkdir()
    (tmp_path / "bag" / "metadata.yaml").write_text(text)
    code, _, err = run("bag-graph", str(tmp_path / "bag"))
    assert code == 2 and err.count("\n") == 1 and problem in err, err


def test_metadata_not_utf8_is_one_line(tmp_path):
    bag = write_bag(tmp_path / "b", "sqlite3", robot_topics())
    (bag / "metadata.yaml").write_bytes(b"rosbag2_bagfile_information:\n  version: \xff\xfe9\n")
    code, _, err = run("bag-info", str(bag))
    assert code == 2 and err.count("\n") == 1 and "not UTF-8" in err


def test_not_a_recording(tmp_path):
    (tmp_path / "x.bag").write_bytes(b"hello")
    (tmp_path / "empty").mkdir()
    for path, problem in ((tmp_path / "x.bag", "not a recording"), (tmp_path / "empty", "without metadata.yaml")):
        code, _, err = run("bag-info", str(path))
        assert code == 2 and problem in err and err.count("\n") == 1
    shutil.rmtree(tmp_path / "empty")


def test_a_damaged_message_of_a_decodable_topic_is_one_line(tmp_path):
    """Found by the bag fuzzer: the first /scan message decodes, a later one holds bytes that are not UTF-8."""
    import sqlite3

    bag = write_bag(tmp_path / "damaged", "sqlite3", robot_topics())
    (db,) = bag.glob("*.db3")
    with sqlite3.connect(db) as con:
        (topic_id,) = con.execute("SELECT id FROM topics WHERE name = '/scan'").fetchone()
        (msg_id, data) = con.execute("SELECT id, data FROM messages WHERE topic_id = ? ORDER BY timestamp "
                                     "LIMIT 1 OFFSET 3", (topic_id,)).fetchone()  # fmt: skip
        con.execute("UPDATE messages SET data = ? WHERE id = ?", (data[:8] + b"\xf3" + data[9:], msg_id))
    code, out, err = run("bag-events", "--dry-run", str(bag))
    assert code == 0 and err.count("\n") == 1 and "/scan (std_msgs/msg/String) skipped: a message" in err, err
    assert sum(1 for line in out.splitlines() if "speed.data" in line) == 21  # the other topics are whole
