"""Mutation fuzz over recordings (issue 25's hostile bags): 0 tracebacks.

Seed recordings of every kind the fleet client reads (rosbag2 sqlite3 and MCAP, plain and in each zstd
compression; rosbag1 plain, bz2 and lz4; ros2/rosbag2's published talker bags) are mutated once per example:
``metadata.yaml`` as text (tests/fuzz/mutation.py) or by a hostile construct (deep nesting, aliases, bytes that
are not UTF-8, a path outside the bag, a compression mode switched on), a storage file as bytes (bits flipped,
hostile integers written over length fields, truncated, zeroed, spliced), or a decompression bomb (a zstd frame
of 3 GiB in place of a message, of a file-compressed storage file, or of an MCAP chunk). Each mutated bag goes
through ``bag-info``, ``bag-graph`` and ``bag-events --dry-run`` of ``python -m continuum.fleet`` in-process:
exit 0, or exit 2 with exactly one line on stderr; an exception escaping ``main`` (a traceback) fails.
Derandomized; CONTINUUM_FUZZ_EXAMPLES=N explores further at random.
"""

from __future__ import annotations

import contextlib
import io
import os
import shutil
import sqlite3
import struct
from collections import Counter
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from continuum.fleet import bags
from continuum.fleet.cli import main
from tests.fleetclient.conftest import robot_topics, write_bag, write_bag1

from .mutation import mutated_text

PUBLISHED = Path(__file__).resolve().parents[1] / "data" / "rosbag2"
EXPLORE = int(os.environ.get("CONTINUUM_FUZZ_EXAMPLES", "0"))
EXAMPLES = EXPLORE or 230
BOMB_SIZE = 3 << 30  # issue 25's bomb inflated to about 3 GiB
OUTCOMES: Counter[str] = Counter()


def zstd_bomb(size: int) -> bytes:
    c = bags.zstd.ZstdCompressor()
    block = bytes(1 << 20)
    return b"".join(c.compress(block) for _ in range(size >> 20)) + c.flush()


def _mcap_record(op: int, body: bytes) -> bytes:
    return bytes([op]) + struct.pack("<Q", len(body)) + body


def _mcap_str(text: str) -> bytes:
    raw = text.encode()
    return struct.pack("<I", len(raw)) + raw


def mcap_with_chunk(payload: bytes, declared: int) -> bytes:
    """A minimal MCAP file (no summary: the reader scans it) whose one chunk holds ``payload`` compressed with
    zstd and declares ``declared`` bytes once inflated."""
    schema = _mcap_record(0x03, struct.pack("<H", 1) + _mcap_str("std_msgs/msg/String") + _mcap_str("ros2msg")
                          + struct.pack("<I", 11) + b"string data")  # fmt: skip
    channel = _mcap_record(0x04, struct.pack("<HH", 1, 1) + _mcap_str("/chatter") + _mcap_str("cdr")
                           + struct.pack("<I", 0))  # fmt: skip
    chunk = _mcap_record(0x06, struct.pack("<QQQI", 0, 1, declared, 0) + _mcap_str("zstd")
                         + struct.pack("<Q", len(payload)) + payload)  # fmt: skip
    header = _mcap_record(0x01, _mcap_str("ros2") + _mcap_str("fuzz"))
    footer = _mcap_record(0x02, struct.pack("<QQI", 0, 0, 0))
    magic = b"\x89MCAP0\r\n"
    return magic + header + schema + channel + chunk + _mcap_record(0x0F, struct.pack("<I", 0)) + footer + magic


@pytest.fixture(scope="module")
def seeds(tmp_path_factory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("seeds")
    out: dict[str, Path] = {}
    for storage in ("sqlite3", "mcap"):
        out[f"{storage}"] = write_bag(root / storage, storage, robot_topics())
        for mode in ("file", "message"):
            out[f"{storage}-{mode}"] = write_bag(root / f"{storage}-{mode}", storage, robot_topics(), compression=mode)
        shutil.copytree(PUBLISHED / storage / "talker", root / f"talker-{storage}")
        out[f"talker-{storage}"] = root / f"talker-{storage}"
    out["mcap-chunks"] = write_bag(root / "mcap-chunks", "mcap", robot_topics(), compression="storage")
    topics = {"/speed": ("std_msgs/msg/Float64", 20.0, 21, lambda t, i: t(data=0.5 * i)),
              "/scan": ("std_msgs/msg/String", 10.0, 11, lambda t, i: t(data="x" * 96))}  # fmt: skip
    for comp in (None, "bz2", "lz4"):
        out[f"bag1-{comp}"] = write_bag1(root / f"run-{comp}.bag", topics, compression=comp)
    return out


@pytest.fixture(scope="module")
def bomb() -> bytes:
    return zstd_bomb(BOMB_SIZE)


@pytest.fixture(scope="module", autouse=True)
def small_limits():
    """Lower limits keep each refused bomb cheap (the default limits stop the same 3 GiB bomb after 256 MiB:
    tests/fleetclient/test_recordings.py); the code path that refuses is the same."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(bags, "MAX_INFLATE", 16 << 20)
        mp.setattr(bags, "MAX_FILE_INFLATE", 32 << 20)
        yield


@pytest.fixture(scope="module")
def work(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("mutants")


def copy_seed(seed: Path, dst: Path) -> Path:
    if dst.exists():
        shutil.rmtree(dst) if dst.is_dir() else dst.unlink()
    if seed.is_dir():
        shutil.copytree(seed, dst)
    else:
        shutil.copyfile(seed, dst)
    for f in [dst, *dst.rglob("*")] if dst.is_dir() else [dst]:
        f.chmod(0o755 if f.is_dir() else 0o644)
    return dst


def storage_files(bag: Path) -> list[Path]:
    return [bag] if bag.is_file() else sorted(f for f in bag.iterdir() if f.name != "metadata.yaml")


HOSTILE_INTS = [0, 1, 0x7F, 0xFF, 0x7FFF, 0xFFFF, 0x7FFFFFFF, 0xFFFFFFFF, 2**63 - 1, 2**64 - 1]
HOSTILE_YAML = [
    lambda t: "rosbag2_bagfile_information: " + "[" * 50_000 + "]" * 50_000,
    lambda t: t.replace("version:", "x:\n" + "".join(" " * (i + 1) + f"k{i}:\n" for i in range(400)) + "version:", 1),
    lambda t: "a: &a [1]\n" + "".join(f"a{i}: &a{i} [*a, *a, *a]\n" for i in range(300)) + t,
    lambda t: t.replace("compression_mode: ''", "compression_mode: message").replace(
        "compression_format: ''", "compression_format: zstd"),
    lambda t: t.replace("compression_mode: ''", "compression_mode: file").replace(
        "compression_format: ''", "compression_format: zstd"),
    lambda t: t.replace("compression_format: ''", "compression_format: lz4").replace(
        "compression_mode: ''", "compression_mode: file"),
    lambda t: t.replace("relative_file_paths:\n", "relative_file_paths:\n  - ../../../../etc/passwd\n", 1),
    lambda t: t.replace("version: ", "version: 1e400 #", 1),
    lambda t: t.replace("storage_identifier: ", "storage_identifier: [1, 2] #", 1),
    lambda t: t + "\n" + "x" * (2 << 20),
]  # fmt: skip


@st.composite
def mutation(draw, seeds: dict[str, Path]) -> tuple[str, str, object]:
    """(seed name, kind, detail) with everything drawn up front, applied by :func:`apply`."""
    name = draw(st.sampled_from(sorted(seeds)))
    seed = seeds[name]
    kinds = ["flip", "int", "truncate", "zero", "splice", "bomb"]
    if seed.is_dir():
        kinds += ["yaml_text", "yaml_text", "yaml_hostile", "yaml_bytes"]
    kind = draw(st.sampled_from(kinds))
    if kind == "yaml_text":
        return name, kind, draw(mutated_text((seed / "metadata.yaml").read_text()))
    if kind == "yaml_hostile":
        return name, kind, draw(st.integers(0, len(HOSTILE_YAML) - 1))
    if kind == "yaml_bytes":
        junk = draw(st.sampled_from([b"\xff", b"\xc3\x28", b"\x00", b"\xed\xa0\x80"]))  # not UTF-8, NUL, a surrogate
        return name, kind, (draw(st.integers(0, 10**6)), junk)
    files = storage_files(seed)
    target = draw(st.integers(0, len(files) - 1))
    size = files[target].stat().st_size
    at = draw(st.integers(0, max(0, size - 1)))
    if kind == "flip":
        return name, kind, (target, [(draw(st.integers(0, max(0, size - 1))), draw(st.integers(1, 255)))
                                     for _ in range(draw(st.integers(1, 8)))])  # fmt: skip
    if kind == "int":
        return name, kind, (target, at, draw(st.sampled_from(HOSTILE_INTS)), draw(st.sampled_from([2, 4, 8])))
    if kind == "splice":
        return name, kind, (target, at, draw(st.binary(min_size=1, max_size=64)))
    if kind == "bomb":
        return name, kind, draw(st.sampled_from(["declared-small", "declared-huge"]))
    return name, kind, (target, at, draw(st.integers(1, 4096)))


def apply(seed: Path, dst: Path, kind: str, detail: object, bomb: bytes) -> Path:
    bag = copy_seed(seed, dst)
    if kind.startswith("yaml"):
        meta = bag / "metadata.yaml"
        if kind == "yaml_text":
            meta.write_text(str(detail), encoding="utf-8", errors="surrogatepass")
        elif kind == "yaml_hostile":
            meta.write_text(HOSTILE_YAML[int(detail)](meta.read_text()))  # type: ignore[call-overload]
        else:
            pos, junk = detail  # type: ignore[misc]
            raw = meta.read_bytes()
            pos %= len(raw)
            meta.write_bytes(raw[:pos] + junk + raw[pos:])
        return bag
    if kind == "bomb":
        return plant_bomb(bag, str(detail), bomb)
    target, *rest = detail  # type: ignore[misc]
    f = storage_files(bag)[target]
    raw = bytearray(f.read_bytes())
    if kind == "flip":
        for pos, bits in rest[0]:
            if raw:
                raw[pos % len(raw)] ^= bits
    elif kind == "int":
        at, value, width = rest
        raw[at : at + width] = (value % (1 << (8 * width))).to_bytes(width, "little")
    elif kind == "truncate":
        del raw[rest[0] :]
    elif kind == "zero":
        at, n = rest
        raw[at : at + n] = bytes(len(raw[at : at + n]))
    elif kind == "splice":
        at, junk = rest
        raw[at:at] = junk
    f.write_bytes(bytes(raw))
    return bag


def plant_bomb(bag: Path, how: str, bomb: bytes) -> Path:
    """A 3 GiB zstd bomb where the recording's kind holds compressed data."""
    if bag.is_file():  # rosbag1: an MCAP file of one bombed chunk instead
        path = bag.with_suffix(".mcap")
        path.write_bytes(mcap_with_chunk(bomb, 1000 if how == "declared-small" else BOMB_SIZE))
        return path
    meta = bag / "metadata.yaml"
    text = meta.read_text()
    files = storage_files(bag)
    if "compression_mode: file" in text:
        files[0].write_bytes(bomb)
    elif "storage_identifier: sqlite3" in text:
        with sqlite3.connect(files[0]) as con:
            con.execute("UPDATE messages SET data = ? WHERE id = (SELECT min(id) FROM messages)", (bomb,))
        meta.write_text(text.replace("compression_mode: ''", "compression_mode: message").replace(
            "compression_format: ''", "compression_format: zstd"))  # fmt: skip
    else:
        for f in files:
            f.write_bytes(mcap_with_chunk(bomb, 1000 if how == "declared-small" else BOMB_SIZE))
    return bag


def run_cli(*argv: str) -> str:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))  # an exception escaping main is a traceback: it fails the example
    text = err.getvalue()
    assert "Traceback" not in text, text[-2000:]
    if code == 2:
        assert text.count("\n") == 1 and text.startswith("error: "), text[-2000:]
        return "refused"
    assert code == 0, f"exit {code}: {text[-2000:]}"
    return "read"


@settings(max_examples=EXAMPLES, deadline=None, derandomize=not EXPLORE, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow,
                                 HealthCheck.data_too_large])  # fmt: skip
@given(data=st.data())
def test_mutated_recordings_never_traceback(seeds, bomb, work, data):
    name, kind, detail = data.draw(mutation(seeds))
    bag = apply(seeds[name], work / "bag", kind, detail, bomb)
    outcomes = [run_cli(cmd, str(bag)) for cmd in ("bag-info", "bag-graph")]
    outcomes.append(run_cli("bag-events", "--dry-run", str(bag)))
    OUTCOMES["mutants"] += 1
    OUTCOMES[f"kind:{kind}"] += 1
    for o in outcomes:
        OUTCOMES[o] += 1


def test_the_fuzzer_ran_enough(capsys):
    """Runs after the fuzz test (definition order): it reached 200+ mutated recordings, every one answered."""
    with capsys.disabled():
        print(f"\nbag fuzz: {dict(sorted(OUTCOMES.items()))}")
    assert OUTCOMES["mutants"] >= 200
    assert OUTCOMES["read"] + OUTCOMES["refused"] == 3 * OUTCOMES["mutants"]
    assert OUTCOMES["kind:bomb"] >= 10 and OUTCOMES["refused"] > 0
