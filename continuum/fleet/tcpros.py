"""Measuring ROS 1 topics by speaking TCPROS, as ``rostopic hz`` and ``rostopic bw`` do, without rospy.

Why not rospy: it lives in the ROS installation's Python (Debian's ``/usr/bin/python3``, or a Noetic
workspace), not in the fleet client's virtualenv, and its version is the robot's. The protocol a subscriber
speaks is small and stable (ROS wiki, "ROS/TCPROS" and "ROS/Master_Slave_APIs"): ask the publishing node's
XML-RPC server ``requestTopic(caller, topic, [["TCPROS"]])`` for a host and port, open a TCP connection, exchange
connection headers (``md5sum=*`` and ``type=*`` accept any type, as ``rostopic``'s AnyMsg does), then read
``uint32 length + payload`` frames. Each publisher is measured on its own connection, so a topic with two
publishers gets two rates.

What is measured per connection, over one window in which every connection is read together (one thread,
``selectors``): the number of messages, their payload bytes (the serialized message, what ``rostopic bw``
counts) and the arrival times of the first and last one. ``rate_hz`` is ``(n - 1) / (last - first)`` (the mean
of the intervals, as ``rostopic hz`` reports), ``msg_bytes`` the mean payload. Payloads are counted and
dropped, never kept: a hostile length of 4 GiB costs no memory.
"""

from __future__ import annotations

import contextlib
import selectors
import socket
import struct
import time
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Link", "TcprosError", "measure", "pack_header", "parse_header"]

#: Largest connection header accepted (real ones carry a message definition: a few to a few dozen KiB).
MAX_HEADER = 1 << 20


class TcprosError(Exception):
    """A publisher could not be reached or spoke something else than TCPROS."""


def pack_header(fields: dict[str, str]) -> bytes:
    body = b"".join(struct.pack("<I", len(f)) + f for f in (f"{k}={v}".encode() for k, v in fields.items()))
    return struct.pack("<I", len(body)) + body


def parse_header(body: bytes) -> dict[str, str]:
    out: dict[str, str] = {}
    at = 0
    while at + 4 <= len(body):
        (n,) = struct.unpack_from("<I", body, at)
        at += 4
        if at + n > len(body):
            raise TcprosError("connection header field runs past the header")
        key, sep, value = body[at : at + n].decode("utf-8", "replace").partition("=")
        if sep:
            out[key] = value
        at += n
    return out


@dataclass
class Link:
    """One subscription to one publisher of one topic, and what was measured on it."""

    topic: str
    publisher: str
    host: str
    port: int
    sock: socket.socket | None = None
    header: dict[str, str] = field(default_factory=dict)
    messages: int = 0
    total_bytes: int = 0
    first: float | None = None
    last: float | None = None
    error: str | None = None
    #: Called with (payload, arrival time) for every counted message, when set (the payload is then kept until
    #: it is complete, up to ``max_payload`` bytes; a longer one is an error): the monitors' topic source.
    on_message: Any = None
    max_payload: int = 64 << 20
    _payload: bytearray = field(default_factory=bytearray)
    _buf: bytearray = field(default_factory=bytearray)
    _have_header: bool = False
    _header_len: int | None = None
    _size: int = 0
    _need: int | None = None  # bytes of the current payload still to drop
    _count_from: float = 0.0

    @property
    def rate_hz(self) -> float | None:
        if self.messages >= 2 and self.first is not None and self.last is not None and self.last > self.first:
            return (self.messages - 1) / (self.last - self.first)
        return None

    @property
    def msg_bytes(self) -> float | None:
        return self.total_bytes / self.messages if self.messages else None

    # ---- protocol --------------------------------------------------------------------------------------
    def feed(self, data: bytes, now: float) -> None:
        """Consume bytes read from the socket: the publisher's header first, then ``uint32 + payload`` frames.
        The buffer holds at most one read plus a header: payload bytes are dropped as they are counted."""
        self._buf += data
        while self._buf:
            if not self._have_header:
                if not self._read_header():
                    return
                self._have_header = True
                continue
            if self._need is None:
                if len(self._buf) < 4:
                    return
                (self._size,) = struct.unpack_from("<I", self._buf)
                del self._buf[:4]
                self._need = self._size
                if self.on_message is not None and self._size > self.max_payload:
                    raise TcprosError(f"a message of {self._size} bytes (more than {self.max_payload})")
            take = min(self._need, len(self._buf))
            if self.on_message is not None:
                self._payload += self._buf[:take]
            del self._buf[:take]
            self._need -= take
            if self._need:
                return
            self._need = None
            if now >= self._count_from:  # a message counts when its last byte arrived: rostopic's callback time
                self.messages += 1
                self.total_bytes += self._size
                self.first = now if self.first is None else self.first
                self.last = now
                if self.on_message is not None:
                    self.on_message(self, bytes(self._payload), now)
            self._payload.clear()

    def _read_header(self) -> bool:
        if self._header_len is None:
            if len(self._buf) < 4:
                return False
            (self._header_len,) = struct.unpack_from("<I", self._buf)
            if self._header_len > MAX_HEADER:
                raise TcprosError(f"connection header of {self._header_len} bytes")
            del self._buf[:4]
        if len(self._buf) < self._header_len:
            return False
        self.header = parse_header(bytes(self._buf[: self._header_len]))
        del self._buf[: self._header_len]
        if "error" in self.header:
            raise TcprosError(f"publisher refused: {self.header['error'][:200]}")
        if self.on_message is None:
            self.header.pop("message_definition", None)  # large, and only decoding needs it
        return True


def connect(link: Link, caller_id: str, timeout: float = 5.0) -> None:
    """Open the link's TCP connection and send the subscriber's header (errors kept on the link)."""
    try:
        sock = socket.create_connection((link.host, link.port), timeout=timeout)
        sock.sendall(pack_header({"callerid": caller_id, "topic": link.topic, "md5sum": "*", "type": "*",
                                  "tcp_nodelay": "1"}))  # fmt: skip
        sock.setblocking(False)
        link.sock = sock
    except OSError as exc:
        link.error = f"cannot connect to {link.host}:{link.port} ({exc.strerror or exc})"


def pump(sel: selectors.BaseSelector, until: float) -> None:
    """Read every registered link until the monotonic time ``until``."""
    while (left := until - time.monotonic()) > 0:
        for key, _ in sel.select(timeout=min(left, 0.5)):
            link = key.data
            try:
                data = link.sock.recv(1 << 16)
                if not data:
                    raise TcprosError("the publisher closed the connection")
                link.feed(data, time.monotonic())
            except (OSError, TcprosError) as exc:
                link.error = str(exc) if isinstance(exc, TcprosError) else f"read failed ({exc})"
                sel.unregister(link.sock)


def measure(links: list[Link], caller_id: str, duration: float, settle: float = 0.0,
            connect_timeout: float = 5.0) -> None:  # fmt: skip
    """Connect every link, read them all for ``duration`` seconds, close them. Messages that arrive during the
    first ``settle`` seconds after the connections opened are not counted (a latched topic's last message,
    a publisher's queue flushed on connect). Errors are kept on each link (``error``), never raised."""
    sel = selectors.DefaultSelector()
    try:
        for link in links:
            connect(link, caller_id, connect_timeout)
            if link.sock is not None:
                sel.register(link.sock, selectors.EVENT_READ, link)
        start = time.monotonic()
        for link in links:
            link._count_from = start + settle
        pump(sel, start + settle + duration)
    finally:
        for link in links:
            if link.sock is not None:
                with contextlib.suppress(OSError):
                    link.sock.close()
        sel.close()


def window(links: list[Link]) -> dict[str, Any]:
    """Per link: measured numbers or the error, for logs and tests."""
    return {f"{x.topic} <- {x.publisher}": (x.error or (x.messages, x.rate_hz, x.msg_bytes)) for x in links}
