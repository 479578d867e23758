"""ROS graphs and STL event streams from recorded robot runs, without ROS: rosbag2 (sqlite3 or MCAP) read with
the pure-Python ``rosbags`` library.

What a bag can honestly tell (and what it cannot):

* **Topics, message types, counts, sizes, times**: every message is stored serialized (CDR) with its receive
  time, so a topic's message rate is ``m / T`` (m messages over its time T in the recording, Eq. 3.12's
  observation window; counted as m - 1 intervals between the first and last message, see ``rate_hz``) and its
  message size is the mean serialized size (the bytes DDS carried, header included).
  Eq. 3.12's ``m * M_size / T`` for a topic is then ``rate_hz * msg_bytes`` (bytes/s), what
  ``continuum.rosgraph/v1`` stores per topic.
* **Publishers and subscribers: not recorded.** rosbag2 keeps per topic its type, serialization format and the
  publishers' offered QoS profiles, but no node names (and the recorder was the only subscriber). Node names
  come from a map the caller gives (``publishers``/``subscribers``: topic -> node names, e.g. from
  ``ros2 topic info -v`` on the robot); a topic without one gets a placeholder publisher named after the topic
  (``/scan`` -> ``scan_pub``) and no subscriber, and the document's ``meta.unnamed_publishers`` lists them.
  The number of publishers per topic the bag's QoS list shows is kept in ``meta.offered_qos_count``.
* **Events for the STL monitors**: each numeric or boolean scalar field of a message is a signal named
  ``<topic>.<field path>`` with ``/`` turned into ``.`` (``/odom`` ``twist.twist.linear.x`` ->
  ``odom.twist.twist.linear.x``: a dotted identifier of the assertion grammar), timestamped in milliseconds
  since the start of the recording (the monitors' clock starts at 0). Arrays are skipped.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rosbags.highlevel import AnyReader, AnyReaderError
from rosbags.typesys import Stores, get_typestore

FORMAT = "continuum.rosgraph/v1"
_NAME = re.compile(r"[^A-Za-z0-9_]+")


class BagError(ValueError):
    """The recording cannot be read (not a rosbag2 directory or file, damaged, unknown message type)."""


@dataclass
class TopicStats:
    name: str
    msgtype: str
    messages: int = 0
    total_bytes: int = 0
    first_ns: int | None = None
    last_ns: int | None = None
    publishers_offered: int = 0

    @property
    def mean_bytes(self) -> float:
        return self.total_bytes / self.messages if self.messages else 0.0


@dataclass
class BagStats:
    path: str
    start_ns: int
    end_ns: int
    topics: dict[str, TopicStats] = field(default_factory=dict)

    @property
    def window_s(self) -> float:
        """The observation window T: from the first to the last message of the recording."""
        return max(0.0, (self.end_ns - self.start_ns) / 1e9)

    def rate_hz(self, topic: str) -> float:
        """Messages per second: ``(m - 1)`` intervals over the time from the topic's first to its last message
        (a 10 Hz topic recorded for 1 s has 11 messages and 10 intervals: 10 Hz, where ``m / T`` would say 11),
        else ``m / T`` over the recording's window; 0 for a recording of one instant."""
        t = self.topics[topic]
        if t.messages >= 2 and t.first_ns is not None and t.last_ns is not None and t.last_ns > t.first_ns:
            return (t.messages - 1) / ((t.last_ns - t.first_ns) / 1e9)
        return t.messages / self.window_s if self.window_s > 0 else 0.0


def _open(path: str | Path) -> AnyReader:
    p = Path(path)
    if not p.exists():
        raise BagError(f"{path}: no such file or directory")
    # The recording's own message definitions come first; the Humble store covers bags recorded without them.
    return AnyReader([p], default_typestore=get_typestore(Stores.ROS2_HUMBLE))


def read_stats(path: str | Path, topics: Iterable[str] | None = None) -> BagStats:
    """Counts, sizes and times per topic (only ``topics`` when given), reading each message once."""
    wanted = set(topics) if topics is not None else None
    try:
        with _open(path) as reader:
            conns = [c for c in reader.connections if wanted is None or c.topic in wanted]
            if wanted is not None and (missing := wanted - {c.topic for c in conns}):
                raise BagError(f"{path}: no topic {sorted(missing)[0]!r} in the recording")
            stats = BagStats(str(path), 0, 0)
            for c in conns:
                t = stats.topics.setdefault(c.topic, TopicStats(c.topic, c.msgtype))
                t.publishers_offered += len(getattr(c.ext, "offered_qos_profiles", None) or [])
            for conn, stamp, raw in reader.messages(connections=conns):
                t = stats.topics[conn.topic]
                t.messages += 1
                t.total_bytes += len(raw)
                t.first_ns = stamp if t.first_ns is None else min(t.first_ns, stamp)
                t.last_ns = stamp if t.last_ns is None else max(t.last_ns, stamp)
    except (AnyReaderError, OSError) as exc:
        raise BagError(f"{path}: not a readable rosbag2 recording ({exc})") from exc
    if not stats.topics:
        raise BagError(f"{path}: the recording has no topics")
    stamps = [s for t in stats.topics.values() for s in (t.first_ns, t.last_ns) if s is not None]
    if not stamps:
        raise BagError(f"{path}: the recording has no messages")
    stats.start_ns, stats.end_ns = min(stamps), max(stamps)
    return stats


def placeholder_publisher(topic: str) -> str:
    return (_NAME.sub("_", topic).strip("_") or "topic") + "_pub"


def rosgraph_from_bag(
    path: str | Path,
    *,
    name: str | None = None,
    publishers: Mapping[str, Sequence[str]] | None = None,
    subscribers: Mapping[str, Sequence[str]] | None = None,
    topics: Iterable[str] | None = None,
) -> dict[str, Any]:
    """A ``continuum.rosgraph/v1`` document from a recording (see the module's docstring for what is derived)."""
    publishers, subscribers = dict(publishers or {}), dict(subscribers or {})
    stats = read_stats(path, topics)
    for what, table in (("publishers", publishers), ("subscribers", subscribers)):
        for topic, names in table.items():
            if topic not in stats.topics:
                raise BagError(f"{what}: topic {topic!r} is not in the recording")
            if isinstance(names, str) or not all(isinstance(n, str) and n for n in names):
                raise BagError(f"{what}: topic {topic!r} needs a list of node names")
    nodes: dict[str, None] = {}
    out_topics = []
    unnamed = []
    for topic in sorted(stats.topics):
        t = stats.topics[topic]
        pubs = list(publishers.get(topic) or [])
        if not pubs:
            pubs = [placeholder_publisher(topic)]
            unnamed.append(topic)
        subs = [s for s in subscribers.get(topic, []) if s not in pubs]
        nodes.update(dict.fromkeys([*pubs, *subs]))
        # rate_hz is each publisher's rate: the topic's messages are shared among its publishers.
        out_topics.append({
            "name": topic,
            "publishers": pubs,
            "subscribers": subs,
            "rate_hz": round(stats.rate_hz(topic) / len(pubs), 6),
            "msg_bytes": round(t.mean_bytes, 3),
            "msg_type": t.msgtype,
        })  # fmt: skip
    return {
        "format": FORMAT,
        "name": name or Path(path).name,
        "nodes": [{"name": n} for n in nodes],
        "topics": out_topics,
        "meta": {
            "source": "rosbag2",
            "window_s": round(stats.window_s, 9),
            "messages": {k: v.messages for k, v in sorted(stats.topics.items())},
            "offered_qos_count": {k: v.publishers_offered for k, v in sorted(stats.topics.items())},
            "unnamed_publishers": unnamed,
        },
    }


# ---- events ---------------------------------------------------------------------------------------------
def signal_prefix(topic: str) -> str:
    """``/robot1/odom`` -> ``robot1.odom``: a topic as the first names of a dotted STL identifier."""
    parts = [_NAME.sub("_", p) for p in topic.split("/") if p]
    return ".".join(p if not p[:1].isdigit() else f"_{p}" for p in parts) or "topic"


def _scalars(msg: Any, prefix: str) -> Iterator[tuple[str, bool | int | float]]:
    """Numeric and boolean scalar fields of a deserialized message, flattened (arrays and strings skipped)."""
    slots = getattr(msg, "__dataclass_fields__", None)
    if slots is None:
        return
    for key in slots:
        if key.startswith("_"):
            continue
        value = getattr(msg, key)
        path = f"{prefix}.{key}"
        if isinstance(value, bool):
            yield path, value
        elif isinstance(value, int | float) and not isinstance(value, bool):
            if isinstance(value, float) and not math.isfinite(value):
                continue  # the events endpoint refuses NaN and infinities: such a sample says nothing
            yield path, value
        elif hasattr(value, "dtype") and getattr(value, "shape", None) == ():  # numpy scalar
            yield path, value.item()
        elif hasattr(value, "__dataclass_fields__"):
            yield from _scalars(value, path)


def events_from_bag(
    path: str | Path, *, topics: Iterable[str] | None = None, signals: Iterable[str] | None = None
) -> Iterator[list[Any]]:
    """``[signal, value, timestamp_ms]`` events, in recording order, for the STL monitors (``POST /events/``).

    ``topics`` limits the topics read; ``signals`` (full signal names) limits what is emitted. Timestamps are
    milliseconds since the recording's start.
    """
    wanted = set(signals) if signals is not None else None
    topic_set = set(topics) if topics is not None else None
    try:
        with _open(path) as reader:
            conns = [c for c in reader.connections if topic_set is None or c.topic in topic_set]
            if topic_set is not None and (missing := topic_set - {c.topic for c in conns}):
                raise BagError(f"{path}: no topic {sorted(missing)[0]!r} in the recording")
            start = reader.start_time
            for conn, stamp, raw in reader.messages(connections=conns):
                try:
                    msg = reader.deserialize(raw, conn.msgtype)
                except Exception as exc:  # the library raises several kinds for a type it cannot decode
                    raise BagError(f"{path}: cannot decode {conn.topic} ({conn.msgtype}): {exc}") from exc
                t_ms = (stamp - start) / 1e6
                for name, value in _scalars(msg, signal_prefix(conn.topic)):
                    if wanted is None or name in wanted:
                        yield [name, value, t_ms]
    except (AnyReaderError, OSError) as exc:
        raise BagError(f"{path}: not a readable rosbag2 recording ({exc})") from exc
