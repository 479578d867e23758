"""ROS graphs and STL event streams from recorded robot runs, without ROS: rosbag1 (``.bag``) and rosbag2
(sqlite3 or MCAP) read with the pure-Python ``rosbags`` library, bounded against hostile files (:mod:`.bags`).

What a bag can honestly tell (and what it cannot):

* **Topics, message types, counts, sizes, times**: every message is stored serialized (CDR) with its receive
  time, so a topic's message rate is ``m / T`` (m messages over its time T in the recording, Eq. 3.12's
  observation window; counted as m - 1 intervals between the first and last message, see ``rate_hz``) and its
  message size is the mean serialized size (the bytes DDS carried, header included).
  Eq. 3.12's ``m * M_size / T`` for a topic is then ``rate_hz * msg_bytes`` (bytes/s), what
  ``continuum.rosgraph/v1`` stores per topic.
* **Publishers: recorded by rosbag1 only.** rosbag1 keeps each publisher's node name (the connection's
  ``callerid``): those name the topic's publishers unless the caller's map names them.
* **Subscribers, and rosbag2's publishers: not recorded.** rosbag2 keeps per topic its type, serialization
  format and the publishers' offered QoS profiles, but no node names (and the recorder was the only subscriber).
  Node names come from a map the caller gives (``publishers``/``subscribers``: topic -> node names, e.g. from
  ``ros2 topic info -v`` on the robot); a topic without one gets a placeholder publisher named after the topic
  (``/scan`` -> ``scan_pub``) and no subscriber, and the document's ``meta.unnamed_publishers`` lists them. The
  number of publishers per topic the bag's QoS list shows is kept in ``meta.offered_qos_count``.
* **Events for the STL monitors**: each numeric or boolean scalar field of a message is a signal named
  ``<topic>.<field path>`` with ``/`` turned into ``.`` (``/odom`` ``twist.twist.linear.x`` ->
  ``odom.twist.twist.linear.x``: a dotted identifier of the assertion grammar), timestamped in milliseconds
  since the start of the recording (the monitors' clock starts at 0). Arrays are skipped. Every type the
  recording defines (or ROS 2 Humble / ROS 1 Noetic defines, for a recording without definitions) is decoded;
  a topic whose type nothing can decode is skipped with one line saying why (``on_skip``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .bags import BagError, open_bag

__all__ = [
    "BagError",
    "BagStats",
    "describe_bag",
    "events_from_bag",
    "read_stats",
    "rosgraph_from_bag",
    "signal_prefix",
]

FORMAT = "continuum.rosgraph/v1"
_NAME = re.compile(r"[^A-Za-z0-9_]+")


@dataclass
class TopicStats:
    name: str
    msgtype: str
    messages: int = 0
    total_bytes: int = 0
    first_ns: int | None = None
    last_ns: int | None = None
    publishers_offered: int = 0
    #: The publishers' node names where the recording keeps them (rosbag1's callerid).
    callerids: list[str] = field(default_factory=list)

    @property
    def mean_bytes(self) -> float:
        return self.total_bytes / self.messages if self.messages else 0.0


@dataclass
class BagStats:
    path: str
    start_ns: int
    end_ns: int
    topics: dict[str, TopicStats] = field(default_factory=dict)
    kind: str = "rosbag2"

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


def _missing(path: str | Path, wanted: set[str] | None, have: Iterable[str]) -> None:
    if wanted is not None and (missing := wanted - set(have)):
        raise BagError(f"{path}: no topic {sorted(missing)[0]!r} in the recording")


def read_stats(path: str | Path, topics: Iterable[str] | None = None) -> BagStats:
    """Counts, sizes and times per topic (only ``topics`` when given), reading each message once (no decoding:
    a topic of a type nothing can decode still has its rate and size)."""
    wanted = set(topics) if topics is not None else None
    with open_bag(path) as bag:
        _missing(path, wanted, bag.topics)
        stats = BagStats(str(path), 0, 0, kind=bag.kind.split()[0])
        for name, info in bag.topics.items():
            if wanted is None or name in wanted:
                stats.topics[name] = TopicStats(name, info.msgtype, publishers_offered=info.offered_qos,
                                                callerids=list(info.callerids))  # fmt: skip
        for conn, stamp, raw in bag.messages(stats.topics):
            t = stats.topics[conn.topic]
            t.messages += 1
            t.total_bytes += len(raw)
            t.first_ns = stamp if t.first_ns is None else min(t.first_ns, stamp)
            t.last_ns = stamp if t.last_ns is None else max(t.last_ns, stamp)
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
        pubs = list(publishers.get(topic) or t.callerids)
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
            "source": stats.kind,
            "window_s": round(stats.window_s, 9),
            "messages": {k: v.messages for k, v in sorted(stats.topics.items())},
            "offered_qos_count": {k: v.publishers_offered for k, v in sorted(stats.topics.items())},
            "unnamed_publishers": unnamed,
        },
    }


def describe_bag(path: str | Path) -> dict[str, Any]:
    """What a recording holds, per topic: type, messages, rate, mean size, publishers (rosbag1) and whether its
    messages can be decoded (the first one is tried) or, in one line, why not."""
    stats = read_stats(path)
    decodable: dict[str, str | None] = {}
    with open_bag(path) as bag:
        for topic in stats.topics:
            first = next(iter(bag.messages([topic])), None)
            if first is None:
                decodable[topic] = "no messages"
                continue
            try:
                bag.decode(first[0], first[2])
                decodable[topic] = None
            except BagError as exc:
                decodable[topic] = str(exc)
    return {
        "path": str(path),
        "kind": stats.kind,
        "window_s": round(stats.window_s, 9),
        "topics": [
            {"name": name, "msg_type": t.msgtype, "messages": t.messages, "rate_hz": round(stats.rate_hz(name), 6),
             "msg_bytes": round(t.mean_bytes, 3), "publishers": t.callerids,
             "decodable": decodable[name] is None, **({"why": decodable[name]} if decodable[name] else {})}
            for name, t in sorted(stats.topics.items())
        ],
    }  # fmt: skip


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
    for key, spec in slots.items():
        # A message type's constants (rcl_interfaces/msg/Log's DEBUG = 10) are fields typed ClassVar: not data.
        if key.startswith("_") or str(getattr(spec, "type", "")).startswith("ClassVar"):
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
    path: str | Path,
    *,
    topics: Iterable[str] | None = None,
    signals: Iterable[str] | None = None,
    on_skip: Callable[[str], None] | None = None,
) -> Iterator[list[Any]]:
    """``[signal, value, timestamp_ms]`` events, in recording order, for the STL monitors (``POST /events/``).

    ``topics`` limits the topics read; ``signals`` (full signal names) limits what is emitted. Timestamps are
    milliseconds since the recording's start. A topic whose messages cannot be decoded is skipped and
    ``on_skip`` hears one line about it (once per topic); a topic named in ``topics`` that cannot be decoded
    is a :class:`BagError` instead (the caller asked for it).
    """
    wanted = set(signals) if signals is not None else None
    topic_set = set(topics) if topics is not None else None
    skipped: dict[str, int] = {}
    with open_bag(path) as bag:
        _missing(path, topic_set, bag.topics)
        start, first = bag.start_ns, True
        for conn, stamp, raw in bag.messages(topic_set):
            if first:  # a damaged summary may claim a later start than the first message: never negative times
                start, first = stamp if start is None else min(start, stamp), False
            if conn.topic in skipped:
                skipped[conn.topic] += 1
                continue
            try:
                msg = bag.decode(conn, raw)
            except BagError as exc:
                if topic_set is not None:
                    raise BagError(f"{path}: cannot decode {conn.topic}: {exc}") from None
                skipped[conn.topic] = 1
                if on_skip is not None:
                    on_skip(f"{conn.topic} ({conn.msgtype}) skipped: {exc}")
                continue
            t_ms = (stamp - (start if start is not None else stamp)) / 1e6
            for name, value in _scalars(msg, signal_prefix(conn.topic)):
                if wanted is None or name in wanted:
                    yield [name, value, t_ms]
