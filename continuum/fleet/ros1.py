"""The live ROS 1 graph of a robot, captured from its master and measured: ``continuum.rosgraph/v1``.

1. The master's XML-RPC API (ROS wiki "ROS/Master_API"): ``getSystemState`` gives every topic's publishers
   and subscribers and every service's providers (the nodes are their union), ``getTopicTypes`` the types,
   ``lookupNode`` each node's XML-RPC URI, where ``getPid`` gives its process id (Slave API).
2. A measurement window of ``duration`` seconds: every publisher of every topic is subscribed to over TCPROS
   (:mod:`.tcpros`) and its messages per second and bytes per message are measured as ``rostopic hz``/``bw``
   do; meanwhile the CPU time and resident memory of each node that runs on this machine are read from
   ``/proc`` (:mod:`.procstat`).
3. Each topic carries ``rate_hz`` (per publisher; ``publisher_rates_hz`` too when its publishers differ by
   more than 5 %), ``msg_bytes`` and ``"measured": true``, or ``"measured": false`` with ``why_unmeasured``
   (no publisher, a publisher that cannot be reached). Each node carries ``cpu`` (cores) and ``memory_mib``
   with ``"measured": true``, or ``"measured": false`` and why (another host, a pid that is not the node's).

The capturing process never registers with the master: it does not appear in the graph it captures.
"""

from __future__ import annotations

import http.client
import socket
import time
import xmlrpc.client
from collections.abc import Iterable
from concurrent.futures import ThreadPoolExecutor
from typing import Any
from urllib.parse import urlsplit

from . import procstat
from .capture_errors import CaptureError
from .tcpros import Link, measure

__all__ = ["CALLER_ID", "CaptureError", "capture_ros1", "check_uri"]

CALLER_ID = "/continuum_capture"
FORMAT = "continuum.rosgraph/v1"
#: Publishers whose rates differ by more than this share get ``publisher_rates_hz``.
SPREAD = 0.05
MAX_NAMES = 100_000  # nodes or topics one master may report


class _Transport(xmlrpc.client.Transport):
    def __init__(self, timeout: float):
        super().__init__()
        self._timeout = timeout

    def make_connection(self, host: Any) -> http.client.HTTPConnection:
        conn = super().make_connection(host)
        conn.timeout = self._timeout
        return conn


def check_uri(uri: str) -> str:
    parts = urlsplit(uri)
    if parts.scheme != "http" or not parts.hostname:
        raise CaptureError(f"master URI {uri[:200]!r} must look like http://HOST:PORT/")
    try:
        parts.port  # noqa: B018  # raises on a port that is not a number in range
    except ValueError:
        raise CaptureError(f"master URI {uri[:200]!r} has a bad port") from None
    return uri


def _proxy(uri: str, timeout: float) -> xmlrpc.client.ServerProxy:
    return xmlrpc.client.ServerProxy(uri, transport=_Transport(timeout), allow_none=True)


def _call(uri: str, method: str, *args: Any, timeout: float) -> Any:
    """A Master/Slave API call: ``[code, status, value]`` -> value; CaptureError otherwise."""
    try:
        answer = getattr(_proxy(uri, timeout), method)(CALLER_ID, *args)
    except (OSError, http.client.HTTPException, xmlrpc.client.Error) as exc:
        what = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc) or type(exc).__name__
        raise CaptureError(f"{uri}: {method} failed ({what[:200]})") from None
    except Exception as exc:  # the expat parser raises its own on a server that is not XML-RPC
        raise CaptureError(f"{uri}: {method}: not an XML-RPC answer ({str(exc)[:200]})") from None
    if not (isinstance(answer, list) and len(answer) == 3 and isinstance(answer[0], int)):
        raise CaptureError(f"{uri}: {method} answered something else than [code, status, value]")
    if answer[0] != 1:
        raise CaptureError(f"{uri}: {method} refused: {str(answer[1])[:200]}")
    return answer[2]


def _pairs(value: Any, what: str) -> dict[str, list[str]]:
    """``[[name, [node, ...]], ...]`` of getSystemState, checked."""
    if not isinstance(value, list) or len(value) > MAX_NAMES:
        raise CaptureError(f"getSystemState: {what} is not a list")
    out: dict[str, list[str]] = {}
    for item in value:
        if not (isinstance(item, list) and len(item) == 2 and isinstance(item[0], str) and isinstance(item[1], list)
                and all(isinstance(n, str) for n in item[1])):  # fmt: skip
            raise CaptureError(f"getSystemState: bad {what} entry {str(item)[:100]}")
        out.setdefault(item[0], [])
        out[item[0]] += [n for n in item[1] if n not in out[item[0]]]
    return out


def _node_info(node: str, master: str, timeout: float) -> dict[str, Any]:
    """The node's XML-RPC URI and pid, or why they are unknown."""
    try:
        uri = _call(master, "lookupNode", node, timeout=timeout)
        if not isinstance(uri, str):
            raise CaptureError("lookupNode answered no URI")
        check_uri(uri)
        pid = _call(uri, "getPid", timeout=timeout)
        if not isinstance(pid, int) or isinstance(pid, bool) or pid <= 0:
            raise CaptureError(f"getPid answered {str(pid)[:40]}")
        return {"uri": uri, "pid": pid}
    except CaptureError as exc:
        return {"error": str(exc)}


def _topic_link(topic: str, publisher: str, uri: str, timeout: float) -> Link:
    try:
        proto = _call(uri, "requestTopic", topic, [["TCPROS"]], timeout=timeout)
        if not (isinstance(proto, list) and len(proto) == 3 and proto[0] == "TCPROS" and isinstance(proto[1], str)
                and isinstance(proto[2], int) and 0 < proto[2] < 65536):  # fmt: skip
            raise CaptureError(f"requestTopic answered {str(proto)[:100]}")
        return Link(topic, publisher, proto[1], proto[2])
    except CaptureError as exc:
        return Link(topic, publisher, "", 0, error=str(exc))


def _proc_target(info: dict[str, Any]) -> str | None:
    """None if the node's process can be measured here, else why not."""
    if "error" in info:
        return info["error"]
    parts = urlsplit(info["uri"])
    if not procstat.is_local_address(parts.hostname or ""):
        return f"runs on {parts.hostname}, not on this machine"
    if not procstat.owns_port(info["pid"], parts.port or 0):
        return f"pid {info['pid']} is not the process serving {info['uri']} here (another pid namespace?)"
    return None


def capture_ros1(master: str, duration: float = 5.0, *, name: str | None = None, timeout: float = 5.0,
                 topics: Iterable[str] | None = None) -> dict[str, Any]:  # fmt: skip
    """Capture and measure the graph of the ROS 1 master at ``master`` (see the module's docstring)."""
    check_uri(master)
    state = _call(master, "getSystemState", timeout=timeout)
    if not isinstance(state, list) or len(state) != 3:
        raise CaptureError(f"{master}: getSystemState answered no [publishers, subscribers, services]")
    pubs, subs, services = (_pairs(state[i], what) for i, what in enumerate(("publishers", "subscribers", "services")))
    types_raw = _call(master, "getTopicTypes", timeout=timeout)
    if not isinstance(types_raw, list):
        raise CaptureError(f"{master}: getTopicTypes answered no list")
    types = {
        t[0]: t[1] for t in types_raw if isinstance(t, list) and len(t) == 2 and all(isinstance(x, str) for x in t)
    }
    wanted = set(topics) if topics is not None else None
    names = sorted(set(pubs) | set(subs))
    if wanted is not None:
        if missing := wanted - set(names):
            raise CaptureError(f"{master}: no topic {sorted(missing)[0]!r} in the graph")
        names = [t for t in names if t in wanted]
    nodes = sorted({n for table in (pubs, subs, services) for ns in table.values() for n in ns})

    with ThreadPoolExecutor(max_workers=8) as pool:
        infos = dict(zip(nodes, pool.map(lambda n: _node_info(n, master, timeout), nodes), strict=True))
        jobs = [(t, p) for t in names for p in pubs.get(t, [])]
        links = list(pool.map(lambda tp: _link_for(tp, infos, timeout), jobs))

    reasons = {n: _proc_target(info) for n, info in infos.items()}
    local = [n for n, why in reasons.items() if why is None]
    before = {n: procstat.sample(infos[n]["pid"]) for n in local}
    settle = min(1.0, duration / 5)
    started = time.time()
    measure([x for x in links if x.error is None], CALLER_ID, duration, settle=settle, connect_timeout=timeout)
    after = {n: procstat.sample(infos[n]["pid"]) for n in local}

    doc_nodes = []
    for n in nodes:
        item: dict[str, Any] = {"name": n}
        b, a = before.get(n), after.get(n)
        cores = procstat.cpu_cores(b, a) if b and a else None
        rss = procstat.rss_mib(infos[n]["pid"]) if n in local else None
        if cores is not None and rss is not None:
            item.update(cpu=round(cores, 4), memory_mib=round(rss, 2), measured=True)
        else:
            item.update(measured=False, why_unmeasured=reasons.get(n) or "the process ended during the window")
        doc_nodes.append(item)

    by_topic: dict[str, list[Link]] = {}
    for link in links:
        by_topic.setdefault(link.topic, []).append(link)
    window = duration
    doc_topics = [_topic_doc(t, pubs.get(t, []), subs.get(t, []), types.get(t, ""), by_topic.get(t, []), window)
                  for t in names]  # fmt: skip
    return {
        "format": FORMAT,
        "name": name or f"ros1-{urlsplit(master).hostname}",
        "nodes": doc_nodes,
        "topics": doc_topics,
        "meta": {
            "source": "ros1 capture",
            "master": master,
            "window_s": window,
            "captured_at": round(started, 3),
            "captured_by": socket.gethostname(),
            "messages": {t: sum(x.messages for x in by_topic.get(t, [])) for t in names},
            "services": {s: ns for s, ns in sorted(services.items())},
            "node_uris": {n: infos[n].get("uri") for n in nodes},
            "pids": {n: infos[n].get("pid") for n in nodes},
        },
    }


def _link_for(tp: tuple[str, str], infos: dict[str, dict[str, Any]], timeout: float) -> Link:
    topic, publisher = tp
    info = infos.get(publisher, {})
    if "uri" not in info:
        return Link(topic, publisher, "", 0, error=info.get("error", "unknown node"))
    return _topic_link(topic, publisher, info["uri"], timeout)


def _topic_doc(name: str, publishers: list[str], subscribers: list[str], msg_type: str, links: list[Link],
               window: float) -> dict[str, Any]:  # fmt: skip
    item: dict[str, Any] = {"name": name, "publishers": publishers, "subscribers": subscribers}
    if msg_type:
        item["msg_type"] = msg_type
    if not publishers:
        return {**item, "rate_hz": 0.0, "msg_bytes": 0.0, "measured": False, "why_unmeasured": "no publisher"}
    rates: dict[str, float] = {}
    sizes: list[tuple[int, int]] = []
    errors = []
    for link in links:
        if link.error is not None:
            errors.append(f"{link.publisher}: {link.error}")
            continue
        # (n - 1) intervals between first and last message, as rostopic hz; fewer than 2 messages: m / T
        rate = link.rate_hz
        rates[link.publisher] = round(rate if rate is not None else link.messages / window, 4)
        sizes.append((link.messages, link.total_bytes))
    messages = sum(m for m, _ in sizes)
    item["msg_bytes"] = round(sum(b for _, b in sizes) / messages, 2) if messages else 0.0
    values = list(rates.values())
    item["rate_hz"] = round(sum(values) / len(values), 4) if values else 0.0
    if values and (max(values) - min(values)) > SPREAD * max(max(values), 1e-9):
        item["publisher_rates_hz"] = rates
    if errors:
        item.update(measured=False, why_unmeasured="; ".join(errors)[:500])
    else:
        item["measured"] = True
        if not messages:
            item["why_no_messages"] = f"no message in the {window:g} s window"
    return item
