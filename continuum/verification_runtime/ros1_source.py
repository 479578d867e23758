"""Live ROS 1 topics as the monitors' events: the topics the registered assertions read, subscribed to over
TCPROS (:mod:`continuum.fleet.tcpros`) and appended to the verification network's event stream.

A signal is ``<topic>.<field path>`` as in recordings (:func:`continuum.fleet.rosbag.signal_prefix`: ``/speed``
``data`` -> ``speed.data``). The source asks the master which topics are published, keeps those whose prefix
starts a signal that a registered monitor depends on, subscribes to every publisher of each, decodes each
message with the definition the publisher sends in its connection header (``rosbags``' ROS 1 deserializer) and
appends one event per wanted scalar field, timestamped in milliseconds of arrival since the source started.

Why one source feeding the handlers' shared stream rather than one subscription per handler: the hand-over of
Fig. 3.43 (:mod:`.handler`) proves that no event is lost or evaluated twice by positions in one totally
ordered stream (the source's position at MIGRATION_START, the destination's at T0). Subscriptions of their own
would give each handler its own arrival order and times, and the positions would no longer mean the same
event on both sides. The stream is also the trace: ``--trace FILE`` writes it as the CSV ``stl_check`` reads.

Run: ``python -m continuum.verification_runtime.ros1_source --ros1 http://robot:11311/ --prefix cv``.
"""

from __future__ import annotations

import argparse
import csv
import os
import selectors
import signal
import sys
import time
from pathlib import Path
from typing import Any

from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from continuum.fleet.capture_errors import CaptureError
from continuum.fleet.ros1 import _call, _node_info, _pairs, _topic_link, check_uri
from continuum.fleet.rosbag import _scalars, signal_prefix
from continuum.fleet.tcpros import Link, connect, pump

from .bus import Bus

__all__ = ["Ros1Source", "main"]

CALLER_ID = "/continuum_monitors"


def ros2_style(ros1_type: str) -> str:
    """``std_msgs/Float64`` -> ``std_msgs/msg/Float64`` (the names ``rosbags`` keys its types by)."""
    pkg, _, name = ros1_type.partition("/")
    return f"{pkg}/msg/{name}" if name and "/msg/" not in ros1_type else ros1_type


class Ros1Source:
    def __init__(self, master: str, bus: Bus, *, timeout: float = 5.0, trace: Path | None = None):
        self.master, self.bus, self.timeout = check_uri(master), bus, timeout
        self.trace = trace
        self.links: list[Link] = []
        self.pending: list[tuple[str, Any, float]] = []
        self.events = 0
        self.rows: list[tuple[float, str, Any]] = []
        self._stores: dict[tuple[str, str], Any] = {}
        self._start = time.monotonic()
        self.signals: set[str] = set()

    def wanted_signals(self) -> set[str]:
        from continuum.engine.verification.stl_monitor import synthesize

        deps: set[str] = set()
        for spec in self.bus.monitors().values():
            deps |= set(synthesize(spec["assertion"], spec.get("constants")).deps)
        return deps

    def subscribe(self) -> list[str]:
        """Subscribe to every publisher of every topic a monitor reads; the topics, sorted."""
        self.signals = self.wanted_signals()
        state = _call(self.master, "getSystemState", timeout=self.timeout)
        pubs = _pairs(state[0], "publishers")
        topics = sorted(t for t in pubs if any(s.startswith(signal_prefix(t) + ".") for s in self.signals))
        for topic in topics:
            for node in pubs[topic]:
                info = _node_info(node, self.master, self.timeout)
                if "uri" not in info:
                    raise CaptureError(f"{topic}: publisher {node}: {info['error']}")
                link = _topic_link(topic, node, info["uri"], self.timeout)
                if link.error:
                    raise CaptureError(f"{topic}: {link.error}")
                link.on_message = self._on_message
                connect(link, CALLER_ID, self.timeout)
                if link.error:
                    raise CaptureError(f"{topic}: {link.error}")
                self.links.append(link)
        self._start = time.monotonic()
        return topics

    def _on_message(self, link: Link, payload: bytes, now: float) -> None:
        msgtype = ros2_style(link.header.get("type", ""))
        key = (msgtype, link.header.get("message_definition", ""))
        if key not in self._stores:
            store = get_typestore(Stores.EMPTY)
            store.register(get_types_from_msg(key[1], msgtype))
            self._stores[key] = store
        msg = self._stores[key].deserialize_ros1(payload, msgtype)
        t_ms = round((now - self._start) * 1000.0, 3)
        for name, value in _scalars(msg, signal_prefix(link.topic)):
            if name in self.signals:
                self.pending.append((name, value, t_ms))
                self.rows.append((t_ms, name, value))

    def run(self, duration: float | None = None, stop: Any = None, slice_s: float = 0.05) -> None:
        """Stream until ``duration`` seconds passed or ``stop()`` is true; events are appended every slice."""
        sel = selectors.DefaultSelector()
        for link in self.links:
            if link.sock is not None:
                sel.register(link.sock, selectors.EVENT_READ, link)
        end = None if duration is None else time.monotonic() + duration
        try:
            while not (stop and stop()) and (end is None or time.monotonic() < end):
                pump(sel, time.monotonic() + slice_s)
                self.flush()
                if broken := [x for x in self.links if x.error]:
                    raise CaptureError(f"{broken[0].topic} <- {broken[0].publisher}: {broken[0].error}")
        finally:
            self.flush()
            for link in self.links:
                if link.sock is not None:
                    link.sock.close()
            sel.close()
            if self.trace is not None:
                self.write_trace(self.trace)

    def flush(self) -> None:
        if self.pending:
            self.bus.publish_events(self.pending)
            self.events += len(self.pending)
            self.pending = []

    def write_trace(self, path: Path) -> None:
        """The events as ``stl_check``'s CSV: a ``time`` column and one per signal, one row per event."""
        names = sorted({n for _, n, _ in self.rows})
        with path.open("w", newline="") as f:
            out = csv.writer(f)
            out.writerow(["time", *names])
            for t, n, v in self.rows:
                value = str(v).lower() if isinstance(v, bool) else repr(v)
                out.writerow([repr(t), *(value if m == n else "" for m in names)])


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description="ROS 1 topics -> the monitors' event stream")
    p.add_argument("--ros1", required=True, metavar="MASTER_URI")
    p.add_argument("--redis", default=os.environ.get("CONTINUUM_REDIS_URL", "redis://127.0.0.1:6379/0"))
    p.add_argument("--prefix", default="cv")
    p.add_argument("--duration", type=float, help="seconds to stream (default: until SIGTERM)")
    p.add_argument("--trace", type=Path, help="also write the events as a CSV trace (stl_check's format)")
    p.add_argument("--end", action="store_true", help="close the event stream when done")
    args = p.parse_args(argv)
    stopping = []
    signal.signal(signal.SIGTERM, lambda *_: stopping.append(1))
    try:
        source = Ros1Source(args.ros1, Bus(args.redis, args.prefix), trace=args.trace)
        topics = source.subscribe()
        print(f"streaming {', '.join(topics) or 'no topic'}", flush=True)
        source.run(args.duration, stop=lambda: bool(stopping))
    except CaptureError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if args.end:
        source.bus.end_events()
    print(f"{source.events} events", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
