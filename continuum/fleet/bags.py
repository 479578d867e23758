"""Opening recordings from strangers: rosbag1 (``.bag``) and rosbag2 (a directory with ``metadata.yaml``, or
one ``.db3``/``.mcap`` file) read with the maintained ``rosbags`` library, with every cost bounded first.

Why not ``rosbags.highlevel.AnyReader`` itself:

* its rosbag2 directory reader pairs the topics of ``metadata.yaml`` with those of the storage file by name,
  type *and* offered QoS: when the two disagree (ros2/rosbag2's own ``talker`` recordings do) every message is
  silently dropped ("no messages" for a bag that holds 20). Here the storage file is the truth: its topics
  table or MCAP channels are read by ``rosbags``' storage readers and ``metadata.yaml`` only says which files,
  which storage and which compression;
* it builds one type store for the whole bag, so one message definition it cannot parse (a service event's
  ``.srv`` text) fails the whole recording with a 30-line grammar error. Here each type gets its own decoder,
  tried on the topic's messages; a type nothing can decode is one line and the other topics still decode;
* decompression is unbounded: a zstd "bomb" of a few kilobytes inflates to gigabytes (MemoryError). Here a
  chunk or a message inflates to at most :data:`MAX_INFLATE` bytes and a file-compressed bag to at most
  :data:`MAX_FILE_INFLATE` bytes on disk; ``rosbags``' tables of chunk decompressors (rosbag1 bz2/lz4, MCAP
  zstd/lz4) are replaced by bounded ones when this module is imported;
* ``metadata.yaml`` is loaded only after its size (:data:`MAX_METADATA`), its nesting depth and its aliases
  were checked on the iterative event stream, so deep YAML is a :class:`BagError`, not a RecursionError.

Anything else a damaged file makes the library raise (a struct error, an SQLite error, a bad UTF-8 name) is a
:class:`BagError` with one line that names the file.
"""

from __future__ import annotations

import bz2
import heapq
import os
import tempfile
from collections.abc import Callable, Iterable, Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from pathlib import Path, PurePath
from typing import Any

import lz4.frame  # type: ignore[import-untyped]
import yaml

try:  # Python 3.14 has zstd in the standard library; rosbags uses the backport before that
    from compression import zstd  # type: ignore[import-not-found,unused-ignore]
except ImportError:  # pragma: no cover - depends on the Python version
    from backports import zstd  # type: ignore[no-redef,unused-ignore]

from rosbags.interfaces import Connection, ConnectionExtRosbag1, MessageDefinitionFormat
from rosbags.rosbag1 import reader as _rosbag1_reader
from rosbags.rosbag2 import storage_mcap as _mcap
from rosbags.rosbag2.storage_mcap import McapReader
from rosbags.rosbag2.storage_sqlite3 import Sqlite3Reader
from rosbags.typesys import Stores, get_types_from_idl, get_types_from_msg, get_typestore

__all__ = ["MAX_FILE_INFLATE", "MAX_INFLATE", "Bag", "BagError", "TopicInfo", "one_line", "open_bag"]


def _env_mib(name: str, default: int) -> int:
    try:
        value = int(os.environ.get(name, default))
    except ValueError:
        value = default
    return max(1, value) * 2**20


#: Bytes one chunk (rosbag1, MCAP) or one message (rosbag2 "message" compression) may inflate to.
MAX_INFLATE = _env_mib("CONTINUUM_BAG_MAX_INFLATE_MIB", 256)
#: Bytes one storage file of a file-compressed rosbag2 may inflate to (written to a temporary directory).
MAX_FILE_INFLATE = _env_mib("CONTINUUM_BAG_MAX_FILE_INFLATE_MIB", 4096)
#: Size of ``metadata.yaml`` (real ones are a few kilobytes) and of one message definition.
MAX_METADATA = 1 * 2**20
MAX_MSGDEF = 1 * 2**20
#: Nesting depth and aliases of ``metadata.yaml`` (real ones nest 5 deep and use no alias).
MAX_YAML_DEPTH = 32
MAX_YAML_ALIASES = 100
#: Storage files one rosbag2 may list.
MAX_FILES = 10_000


class BagError(ValueError):
    """The recording cannot be read (not a recording, damaged, too large once inflated)."""


def _size(n: int) -> str:
    return f"{n // 2**20} MiB" if n >= 2**20 else f"{n} bytes"


def one_line(exc: BaseException, limit: int = 300) -> str:
    """An exception as one short line: its message's lines joined (a grammar error spans many), cut at
    ``limit`` characters, else its type's name."""
    text = " ".join(line.strip() for line in str(exc).splitlines() if line.strip()) or type(exc).__name__
    return text if len(text) <= limit else text[: limit - 3] + "..."


# ---- bounded decompression -------------------------------------------------------------------------------
def _inflate(data: bytes, make: Callable[[], Any], limit: int, what: str) -> bytes:
    """Decompress ``data`` (one or more concatenated frames) to at most ``limit`` bytes."""
    out = bytearray()
    rest = bytes(data)
    while rest:
        d = make()
        try:
            out += d.decompress(rest, max_length=limit + 1 - len(out))
        except Exception as exc:  # each codec has its own error type
            raise BagError(f"{what}: damaged compressed data ({one_line(exc)})") from None
        if len(out) > limit:
            raise BagError(f"{what} inflates to more than {_size(limit)} (a decompression bomb?)")
        if not d.eof:
            raise BagError(f"{what}: compressed data ends early")
        rest = d.unused_data or b""
        if not rest.strip(b"\0"):  # padding after the last frame
            break
    return bytes(out)


def inflate_zstd(data: bytes, limit: int | None = None, what: str = "a message") -> bytes:
    return _inflate(data, zstd.ZstdDecompressor, MAX_INFLATE if limit is None else limit, what)


def _inflate_lz4(data: bytes, limit: int, what: str) -> bytes:
    return _inflate(data, lz4.frame.LZ4FrameDecompressor, limit, what)


def _inflate_bz2(data: bytes, limit: int, what: str) -> bytes:
    return _inflate(data, bz2.BZ2Decompressor, limit, what)


def _mcap_chunk(inflate: Callable[[bytes, int, str], bytes]) -> Callable[[bytes, int], bytes]:
    def decompress(data: bytes, size: int) -> bytes:
        # The chunk declares its inflated size: a chunk that declares more than the limit, or inflates to more
        # than it declared, is refused before the memory is spent.
        if size > MAX_INFLATE:
            raise BagError(f"an MCAP chunk declares {size} bytes inflated, more than {_size(MAX_INFLATE)}")
        return inflate(data, size, "an MCAP chunk")

    return decompress


def _rosbag1_chunk(inflate: Callable[[bytes, int, str], bytes]) -> Callable[[bytes], bytes]:
    return lambda data: inflate(data, MAX_INFLATE, "a rosbag1 chunk")


def _bound_library_decompressors() -> None:
    """Replace ``rosbags``' chunk decompressors (unbounded ``zstd.decompress``, ``lz4.frame.decompress``,
    ``bz2.decompress``) by bounded ones. The readers look the function up in these tables for every chunk."""
    _mcap.DECOMPRESSORS["zstd"] = _mcap_chunk(lambda d, n, w: inflate_zstd(d, n, w))
    _mcap.DECOMPRESSORS["lz4"] = _mcap_chunk(_inflate_lz4)
    _rosbag1_reader.decompressors["bz2"] = _rosbag1_chunk(_inflate_bz2)
    _rosbag1_reader.decompressors["lz4"] = _rosbag1_chunk(_inflate_lz4)


_bound_library_decompressors()


# ---- metadata.yaml ---------------------------------------------------------------------------------------
def load_metadata(path: Path) -> dict[str, Any]:
    """``rosbag2_bagfile_information`` of ``metadata.yaml``, with size, depth and aliases checked first."""
    try:
        if path.stat().st_size > MAX_METADATA:
            raise BagError(f"{path}: larger than {MAX_METADATA // 2**20} MiB")
        text = path.read_bytes().decode("utf-8")
    except UnicodeDecodeError as exc:
        raise BagError(f"{path}: not UTF-8 (byte {exc.start})") from None
    except OSError as exc:
        raise BagError(f"{path}: {exc.strerror or one_line(exc)}") from None
    loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    try:
        depth = aliases = 0
        for event in yaml.parse(text, Loader=loader):  # events: iterative, nothing composed yet
            if isinstance(event, yaml.CollectionStartEvent):
                depth += 1
                if depth > MAX_YAML_DEPTH:
                    raise BagError(f"{path}: nested deeper than {MAX_YAML_DEPTH} levels")
            elif isinstance(event, yaml.CollectionEndEvent):
                depth -= 1
            elif isinstance(event, yaml.AliasEvent):
                aliases += 1
                if aliases > MAX_YAML_ALIASES:
                    raise BagError(f"{path}: more than {MAX_YAML_ALIASES} YAML aliases")
        doc = yaml.load(text, Loader=loader)  # a safe loader (CSafeLoader or SafeLoader)
    except yaml.YAMLError as exc:
        raise BagError(f"{path}: not YAML ({one_line(exc)})") from None
    info = doc.get("rosbag2_bagfile_information") if isinstance(doc, dict) else None
    if not isinstance(info, dict):
        raise BagError(f"{path}: no rosbag2_bagfile_information mapping")
    return info


@dataclass(frozen=True)
class _Layout:
    storage: str  # sqlite3 or mcap
    files: list[Path]
    compression: str | None  # None, "file" or "message" (zstd)


def _layout(directory: Path) -> _Layout:
    info = load_metadata(directory / "metadata.yaml")
    version = info.get("version")
    if not isinstance(version, int) or isinstance(version, bool) or not 1 <= version <= 9:
        raise BagError(f"{directory}: metadata version {version!r} is not one of 1..9")
    storage = info.get("storage_identifier")
    if storage not in ("sqlite3", "mcap"):
        raise BagError(f"{directory}: storage {str(storage)[:40]!r} is not sqlite3 or mcap")
    names = info.get("relative_file_paths")
    if not isinstance(names, list) or not names or not all(isinstance(n, str) and n for n in names):
        raise BagError(f"{directory}: relative_file_paths must be a list of file names")
    if len(names) > MAX_FILES:
        raise BagError(f"{directory}: more than {MAX_FILES} storage files")
    mode = str(info.get("compression_mode") or "").lower()
    fmt = str(info.get("compression_format") or "").lower()
    if mode in ("", "none"):
        compression = None
    elif mode in ("file", "message"):
        if fmt != "zstd":
            raise BagError(f"{directory}: compression format {fmt[:40]!r} is not zstd")
        compression = mode
    else:
        raise BagError(f"{directory}: compression mode {mode[:40]!r} is not file or message")
    # A name, never a path: "../../etc/passwd" in a stranger's metadata reads nothing outside the bag.
    files = [directory / PurePath(n).name for n in names]
    for f in files:
        if not f.is_file():
            raise BagError(f"{directory}: storage file {f.name!r} is missing")
    return _Layout(storage, files, compression)


def _inflate_file(src: Path, dst: Path) -> None:
    """A file-compressed storage file, inflated to ``dst`` with at most :data:`MAX_FILE_INFLATE` bytes (streamed:
    a megabyte in memory at a time)."""
    written = 0
    try:
        with src.open("rb") as raw, zstd.open(raw, "rb") as fin, dst.open("wb") as fout:
            while block := fin.read(1 << 20):
                written += len(block)
                if written > MAX_FILE_INFLATE:
                    raise BagError(f"{src} inflates to more than {_size(MAX_FILE_INFLATE)}")
                fout.write(block)
    except (zstd.ZstdError, EOFError) as exc:
        raise BagError(f"{src}: damaged compressed data ({one_line(exc)})") from None


# ---- the bag ---------------------------------------------------------------------------------------------
@dataclass
class TopicInfo:
    """One topic of a recording: its type, its connections and what the recording says about publishers."""

    name: str
    msgtype: str
    connections: list[Connection] = field(default_factory=list)
    #: rosbag1 records each publisher's node name (``callerid``); rosbag2 records none.
    callerids: list[str] = field(default_factory=list)
    #: rosbag2 records each publisher's offered QoS profile (one per publisher).
    offered_qos: int = 0


class _Decoder:
    """Decodes one message type: the recording's own definition first, then the distribution's (ROS 2 Humble
    or ROS 1 Noetic) where it has the type. The first that decodes the topic's first message exactly (the
    deserializers check the size) is kept; if none does, the type is undecodable with the first reason."""

    def __init__(self, candidates: list[tuple[Any, str]], reasons: list[str], ros1: bool):
        self.candidates, self.reasons, self.ros1 = candidates, reasons, ros1
        self.chosen: Any = None
        self.failed: str | None = None if candidates else (reasons[0] if reasons else "no definition")

    def __call__(self, raw: bytes, msgtype: str) -> Any:
        if self.failed is not None:
            raise BagError(self.failed)
        if self.chosen is not None:
            try:
                return self._run(self.chosen, raw, msgtype)
            except Exception as exc:  # a damaged message of a type that decoded before
                raise BagError(f"a message of {msgtype} does not decode ({one_line(exc, 160)})") from None
        errors = []
        for store, _source in self.candidates:
            try:
                msg = self._run(store, raw, msgtype)
            except Exception as exc:  # the deserializers raise several kinds on data of another shape
                errors.append(one_line(exc))
                continue
            self.chosen = store
            return msg
        self.failed = (self.reasons + errors)[0] if self.reasons + errors else "cannot decode"
        raise BagError(self.failed)

    def _run(self, store: Any, raw: bytes, msgtype: str) -> Any:
        return store.deserialize_ros1(raw, msgtype) if self.ros1 else store.deserialize_cdr(raw, msgtype)


class Bag:
    """An open recording: its topics, its messages in time order, and a decoder per message type."""

    def __init__(self, path: Path, kind: str, readers: list[Any], compression: str | None, ros1: bool):
        self.path, self.kind, self.ros1 = path, kind, ros1
        self._readers, self._compression = readers, compression
        self.topics: dict[str, TopicInfo] = {}
        for reader in readers:
            for conn in reader.connections:
                topic = self.topics.setdefault(conn.topic, TopicInfo(conn.topic, conn.msgtype))
                topic.connections.append(conn)
                if isinstance(conn.ext, ConnectionExtRosbag1):
                    if conn.ext.callerid and conn.ext.callerid not in topic.callerids:
                        topic.callerids.append(conn.ext.callerid)
                else:
                    topic.offered_qos = max(topic.offered_qos, len(getattr(conn.ext, "offered_qos_profiles", [])))
        self._decoders: dict[tuple[str, str], _Decoder] = {}
        self._default: Any = None

    @property
    def start_ns(self) -> int | None:
        """The recording's first message time (every topic's), None for a recording without messages."""
        starts = []
        for reader in self._readers:
            meta = getattr(reader, "metadata", None)  # rosbag2 storage readers
            start = meta.start_time if meta is not None else reader.start_time
            if isinstance(start, int) and start < 2**63 - 1 and (meta is None or meta.message_count):
                starts.append(start)
        return min(starts) if starts else None

    def messages(self, topics: Iterable[str] | None = None) -> Iterator[tuple[Connection, int, bytes]]:
        """``(connection, receive time in ns, serialized message)`` in time order over every storage file."""
        wanted = set(self.topics) if topics is None else set(topics)
        streams = []
        for reader in self._readers:
            conns = [c for c in reader.connections if c.topic in wanted]
            if conns:
                streams.append(reader.messages(conns))
        merged = streams[0] if len(streams) == 1 else heapq.merge(*streams, key=lambda m: m[1])
        try:
            for conn, stamp, raw in merged:
                if self._compression == "message":
                    raw = inflate_zstd(raw, what=f"a message of {conn.topic}")
                yield conn, stamp, raw
        except BagError:
            raise
        except Exception as exc:  # a damaged chunk or page makes the library raise many kinds
            raise BagError(f"{self.path}: damaged recording ({one_line(exc)})") from None

    def decoder(self, conn: Connection) -> _Decoder:
        key = (conn.msgtype, conn.msgdef.data)
        if (found := self._decoders.get(key)) is None:
            found = self._decoders[key] = self._make_decoder(conn)
        return found

    def decode(self, conn: Connection, raw: bytes) -> Any:
        """The deserialized message; :class:`BagError` with one line if its type cannot be decoded."""
        return self.decoder(conn)(raw, conn.msgtype)

    def _make_decoder(self, conn: Connection) -> _Decoder:
        candidates: list[tuple[Any, str]] = []
        reasons: list[str] = []
        msgdef = conn.msgdef
        if msgdef.format != MessageDefinitionFormat.NONE:
            try:
                if len(msgdef.data) > MAX_MSGDEF:
                    raise BagError(f"longer than {MAX_MSGDEF // 2**20} MiB")
                store = get_typestore(Stores.EMPTY)
                store.register(_parse_definition(msgdef.format, msgdef.data, conn.msgtype))
                if conn.msgtype not in store.fielddefs:
                    raise BagError("it does not define the type itself")
                candidates.append((store, "recording"))
            except Exception as exc:  # the grammar, the type system and our checks each raise their own
                what = "service event type" if "/srv/" in conn.msgtype else "definition"
                reasons.append(f"cannot read the recording's {what} {conn.msgtype} ({one_line(exc, 160)})")
        if self._default is None:
            self._default = get_typestore(Stores.ROS1_NOETIC if self.ros1 else Stores.ROS2_HUMBLE)
        if conn.msgtype in self._default.fielddefs:
            candidates.append((self._default, "distribution"))
        elif not candidates:
            distro = "ROS 1 Noetic" if self.ros1 else "ROS 2 Humble"
            reasons.append(f"{conn.msgtype}: no definition in the recording and none in {distro}")
        return _Decoder(candidates, reasons, self.ros1)


def _parse_definition(fmt: MessageDefinitionFormat, text: str, msgtype: str) -> dict[str, Any]:
    if fmt == MessageDefinitionFormat.MSG:
        return dict(get_types_from_msg(text, msgtype))
    sep = "=" * 80 + "\n"
    typs: dict[str, Any] = {}
    parts = text.split(sep)[1:] if text.startswith(f"{sep}IDL: ") else [text]
    for part in parts:
        idl = part.split("\n", 1)[1] if part.startswith("IDL: ") else part
        typs.update(get_types_from_idl(idl))
    return typs


def _open_storage(path: Path, storage: str) -> Any:
    reader = (Sqlite3Reader if storage == "sqlite3" else McapReader)(path)
    reader.open()
    return reader


def _kind_of(path: Path) -> str:
    if path.is_dir():
        if (path / "metadata.yaml").is_file():
            return "rosbag2"
        raise BagError(f"{path}: a directory without metadata.yaml is not a rosbag2 recording")
    with path.open("rb") as f:
        head = f.read(16)
    if head.startswith(b"#ROSBAG V2.0"):
        return "rosbag1"
    if head.startswith(b"\x89MCAP0\r\n"):
        return "mcap"
    if head.startswith(b"SQLite format 3\0"):
        return "sqlite3"
    raise BagError(f"{path}: not a recording (rosbag1 .bag, rosbag2 directory, .db3 or .mcap file)")


@contextmanager
def open_bag(path: str | Path) -> Iterator[Bag]:
    """Open a recording; every error while opening or reading it is a :class:`BagError` with one line."""
    p = Path(path)
    if not p.exists():
        raise BagError(f"{path}: no such file or directory")
    with ExitStack() as stack:
        try:
            kind = _kind_of(p)
            compression = None
            if kind == "rosbag1":
                reader = _rosbag1_reader.Reader(p)
                reader.open()
                stack.callback(reader.close)
                readers = [reader]
            elif kind == "rosbag2":
                layout = _layout(p)
                compression = layout.compression
                files = layout.files
                if compression == "file":
                    tmp = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="continuum-bag-")))
                    inflated = []
                    for f in files:
                        _inflate_file(f, tmp / (f.stem if f.suffix == ".zstd" else f.name))
                        inflated.append(tmp / (f.stem if f.suffix == ".zstd" else f.name))
                    files = inflated
                    compression = None
                readers = []
                for f in files:
                    reader = _open_storage(f, layout.storage)
                    stack.callback(reader.close)
                    readers.append(reader)
                kind = f"rosbag2 {layout.storage}"
            else:
                reader = _open_storage(p, kind)
                stack.callback(reader.close)
                readers = [reader]
                kind = f"rosbag2 {kind}"
            bag = Bag(p, kind, readers, compression, ros1=kind == "rosbag1")
        except BagError:
            raise
        except Exception as exc:  # a damaged file makes the library raise many kinds (struct, SQLite, KeyError)
            raise BagError(f"{path}: not a readable recording ({one_line(exc)})") from None
        yield bag
