"""A ``continuum.cluster/v1`` document as a :class:`Platform`: the cluster graph G^c of HEFT4K (thesis 3.3.2).

One processor per node, named after it, with the node's ``class`` (default ``cpu``; what DAG task costs
name besides node names), ``speed`` (default 1) and ``cores`` = the node's whole CPUs (``cpu``, at least
1), so that HEFT4K can use every CPU of a node (spec 02 section 6.3). Links carry ``bandwidth_mbps``
(Mbit/s) and ``latency_ms``; the platform works in Mbit and ms, so a link moves ``bandwidth_mbps / 1000``
Mbit per ms. Nodes without a direct link are joined over the shortest path (``route=True``); the path rule
defaults to OSPF (least sum of 1/bandwidth, stored and forwarded at each hop), the reading of spec 02
section 6.1, and can be ``"latency"`` instead. Pairs with no path at all use the optional document-level
``default_bandwidth_mbps`` / ``default_latency_ms``; without them such transfers are free, as in the
clusters app.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from .errors import InputError
from .platform import Link, Platform, Processor

FORMAT = "continuum.cluster/v1"


def cluster_platform(doc: Mapping[str, Any], routing: str = "ospf") -> Platform:
    """Read a ``continuum.cluster/v1`` document into a routed, multi-core :class:`Platform`."""
    if not isinstance(doc, Mapping):
        raise InputError("a cluster document must be a JSON object")
    fmt = doc.get("format", FORMAT)
    if fmt != FORMAT:
        raise InputError(f"unsupported format {fmt!r}, expected {FORMAT!r}", "format")
    raw_nodes = doc.get("nodes")
    if not isinstance(raw_nodes, list) or not raw_nodes:
        raise InputError("'nodes' must be a non-empty list", "nodes")
    procs = [_node(i, raw) for i, raw in enumerate(raw_nodes)]
    names = [p.id for p in procs]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise InputError(f"duplicate node name {dup[0]!r}", "nodes")
    raw_links = doc.get("links") or []
    if not isinstance(raw_links, list):
        raise InputError("'links' must be a list", "links")
    links = [_link(i, raw, set(names)) for i, raw in enumerate(raw_links)]
    default_bw = doc.get("default_bandwidth_mbps")
    if default_bw is not None:
        default_bw = _positive(default_bw, "default_bandwidth_mbps", "default_bandwidth_mbps") / 1000.0
    default_lat = _nonneg(doc.get("default_latency_ms", 0.0), "default_latency_ms", "default_latency_ms")
    return Platform(procs, bandwidth=default_bw, latency=default_lat, links=links, route=True, routing=routing)


def _node(index: int, raw: Any) -> Processor:
    if not isinstance(raw, Mapping):
        raise InputError(f"nodes[{index}] must be an object", "nodes")
    name = raw.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"nodes[{index}] has no string 'name'", "nodes")
    cpu = _positive(raw.get("cpu", 1), f"node {name!r} cpu", "nodes")
    speed = _positive(raw.get("speed", 1.0), f"node {name!r} speed", "nodes")
    cls = raw.get("class", "cpu")
    if not isinstance(cls, str) or not cls:
        raise InputError(f"node {name!r} has an invalid class {cls!r}", "nodes")
    return Processor(name, cls, speed, max(1, math.floor(cpu)))


def _link(index: int, raw: Any, names: set[str]) -> Link:
    if not isinstance(raw, Mapping):
        raise InputError(f"links[{index}] must be an object", "links")
    src, dst = raw.get("src"), raw.get("dst")
    for end in (src, dst):
        if end not in names:
            raise InputError(f"links[{index}] ({src}-{dst}) refers to unknown node {end!r}", "links")
    if src == dst:
        raise InputError(f"links[{index}] joins node {src!r} to itself", "links")
    if "bandwidth_mbps" not in raw:
        raise InputError(f"link {src}-{dst} has no 'bandwidth_mbps'", "links")
    bw = _positive(raw["bandwidth_mbps"], f"link {src}-{dst} bandwidth_mbps", "links")
    lat = _nonneg(raw.get("latency_ms", 0.0), f"link {src}-{dst} latency_ms", "links")
    return Link(src, dst, bw / 1000.0, lat)


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return None
    return float(value)


def _positive(value: Any, what: str, field: str) -> float:
    x = _number(value)
    if x is None or x <= 0:
        raise InputError(f"{what} must be a positive number, not {value!r}", field)
    return x


def _nonneg(value: Any, what: str, field: str) -> float:
    x = _number(value)
    if x is None or x < 0:
        raise InputError(f"{what} must be a non-negative number, not {value!r}", field)
    return x
