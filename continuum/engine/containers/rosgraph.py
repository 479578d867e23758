"""ROS computation graphs: ROS nodes, the topics they publish and subscribe, and the bandwidth between them.

Thesis Section 3.2.1 ("From a ROS graph to containers"): ROS nodes are the vertices; two ROS nodes are joined
when they exchange data over at least one topic, and the edge weight is the communication bandwidth of
Eq. (3.12), ``bandwidth(vi, vj) = n_topics * m * M_size / T``, collected at design level L1.

Readings taken here (spec 02, sections 1.2 and 2.2):

* Eq. (3.12) is ambiguous: if ``m`` already counts the messages of every shared topic, multiplying by
  ``n_topics`` counts them twice. The default ``mode="per_topic"`` sums ``m_k * size_k / T`` over the shared
  topics ``k`` (both directions); ``mode="literal"`` multiplies that by the number of shared topics, which is
  Eq. (3.12) to the letter (with ``M_size`` the message-weighted mean size). :func:`eq_3_12` is the formula
  itself. Units: bytes per second.
* Two ROS nodes "share" a topic when one publishes it and the other subscribes to it: two subscribers of the
  same topic exchange nothing. A topic's ``rate_hz`` is the rate of *each* publisher; every subscriber
  receives every message.
* Abstraction levels (Fig. 3.19): ``mission``, ``macro`` (macro-functionality), ``functionality``
  (functionality/controller) and ``driver``. A level given in the input wins; otherwise
  :func:`propose_levels` proposes one from the graph's structure (heuristic in its docstring).

Readers (:func:`load_rosgraph` guesses which): the ``continuum.rosgraph/v1`` contract, the Autoware reference
system JSON (``ros-realtime/reference-system``), iRobot's ``ros2-performance`` topology JSON, and a Graphviz
``.dot`` file as rqt_graph exports it (parsed by the small parser in this module; no pydot needed).
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any, TypeGuard

from continuum.engine.core import limits
from continuum.engine.core.artifact_names import check_package
from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import check_text_file, loads_json

__all__ = [
    "FORMAT",
    "IROBOT_HEADER_BYTES",
    "LEVELS",
    "LEVEL_ALIASES",
    "MODES",
    "PINS",
    "READERS",
    "RosGraph",
    "RosNode",
    "Topic",
    "eq_3_12",
    "from_autoware",
    "from_dot",
    "from_irobot",
    "guess_json_format",
    "irobot_msg_bytes",
    "load_rosgraph",
    "natural_key",
    "pair",
    "parse_dot",
    "propose_levels",
]

FORMAT = "continuum.rosgraph/v1"
LEVELS = ("mission", "macro", "functionality", "driver")
#: Long names used in the spec / thesis figure, accepted as aliases.
LEVEL_ALIASES = {
    "macro_functionality": "macro",
    "macro-functionality": "macro",
    "functionality_controller": "functionality",
    "functionality/controller": "functionality",
    "controller": "functionality",
    "drivers": "driver",
}
MODES = ("per_topic", "literal")
#: A ROS node's pin: ``robot`` keeps it on the robot's boards, ``free`` lets the placement move it anywhere
#: (how an operator unpins a driver); no pin: drivers stay on the robot, the rest is free
#: (:mod:`continuum.engine.containers.robot_pinning`).
PINS = ("robot", "free")
#: Autoware reference-system node types that talk to hardware: its sensors (timer sources) and command sinks.
AUTOWARE_DRIVER_TYPES = ("sensor", "command")


# ---- natural ordering ---------------------------------------------------------------------------
@lru_cache(maxsize=1 << 16)  # a pure function of the name; pair() calls it twice per lookup, sorts once per item
def natural_key(name: str) -> tuple:
    """Sort key where ``v2 < v10`` (spec 2.5: "lexicographic" must be natural order)."""
    parts = re.split(r"(\d+)", name)
    return (*(int(p) if i % 2 else p.casefold() for i, p in enumerate(parts)), name)


def pair(a: str, b: str) -> tuple[str, str]:
    """The canonical key of an undirected pair of names."""
    return (a, b) if natural_key(a) <= natural_key(b) else (b, a)


# ---- the formula itself -------------------------------------------------------------------------
def eq_3_12(n_topics: int, messages: float, avg_msg_bytes: float, window_s: float) -> float:
    """Eq. (3.12) to the letter: ``n_topics * m * M_size / T`` (bytes per second)."""
    if window_s <= 0:
        raise InputError(f"observation window T must be positive, got {window_s!r}")
    if n_topics < 0 or messages < 0 or avg_msg_bytes < 0:
        raise InputError("n_topics, messages and message size must be non-negative")
    return n_topics * messages * avg_msg_bytes / window_s


# ---- the graph ----------------------------------------------------------------------------------
@dataclass(frozen=True)
class RosNode:
    name: str
    level: str | None = None
    #: Functional area ("arm control", "vision"): a context groups nodes sharing functional properties.
    context: str = ""
    #: Informational: "ros", "manufacturer", "user".
    origin: str = ""
    #: CPU demand in cores and memory demand in MiB (the resource profile of spec 2.6).
    cpu: float = 0.0
    memory_mib: float = 0.0
    packages: tuple[str, ...] = ()
    #: One of :data:`PINS`, or ``None`` (the level decides).
    pin: str | None = None
    #: Whether ``cpu``/``memory_mib`` were measured on the running node (a live capture), and if not, why;
    #: ``None``: the document does not say (written by hand, a design file).
    measured: bool | None = None
    why_unmeasured: str = ""


@dataclass(frozen=True)
class Topic:
    name: str
    publishers: tuple[str, ...]
    subscribers: tuple[str, ...]
    #: Messages per second of each publisher (publisher name -> Hz).
    rates: Mapping[str, float]
    msg_bytes: float
    msg_type: str = ""
    #: Whether rate and size were measured on the running system (a live capture), and if not, why;
    #: ``None``: the document does not say.
    measured: bool | None = None
    why_unmeasured: str = ""

    def rate(self, publisher: str) -> float:
        return self.rates.get(publisher, 0.0)


@dataclass
class RosGraph:
    """A validated ROS graph. ``packages`` (optional) maps package name -> {"size_mib", "archs"}."""

    name: str
    nodes: dict[str, RosNode]
    topics: dict[str, Topic]
    packages: dict[str, dict[str, Any]] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)

    # ---- construction -------------------------------------------------------------------------
    @classmethod
    def build(cls, name: str, nodes: Iterable[RosNode], topics: Iterable[Topic], **kwargs: Any) -> RosGraph:
        """Build and validate. ROS nodes named only by a topic are created with default attributes."""
        table: dict[str, RosNode] = {}
        for node in nodes:
            if node.name in table:
                raise InputError(f"duplicate ROS node name {node.name!r}", "nodes")
            table[node.name] = node
        topic_table: dict[str, Topic] = {}
        for topic in topics:
            if topic.name in topic_table:
                raise InputError(f"duplicate topic {topic.name!r}", "topics")
            topic_table[topic.name] = topic
            for member in (*topic.publishers, *topic.subscribers):
                table.setdefault(member, RosNode(member))
        graph = cls(name=name, nodes=table, topics=topic_table, **kwargs)
        graph.validate()
        return graph

    def validate(self) -> None:
        # Every reader ends here: the graph-size limits hold for every format.
        limits.check("nodes", len(self.nodes))
        limits.check("topics", len(self.topics), name="links")
        for node in self.nodes.values():
            if node.level is not None and node.level not in LEVELS:
                raise InputError(f"ROS node {node.name!r} has unknown level {node.level!r}", "nodes")
            if node.pin is not None and node.pin not in PINS:
                raise InputError(f"ROS node {node.name!r} has unknown pin {node.pin!r}", "nodes")
            for what, value in (("cpu", node.cpu), ("memory_mib", node.memory_mib)):
                if not _finite_nonneg(value):
                    raise InputError(f"ROS node {node.name!r} has invalid {what} {value!r}", "nodes")
        for topic in self.topics.values():
            if not _finite_nonneg(topic.msg_bytes):
                raise InputError(f"topic {topic.name!r} has invalid message size {topic.msg_bytes!r}", "topics")
            for pub, hz in topic.rates.items():
                if pub not in topic.publishers:
                    raise InputError(f"topic {topic.name!r} gives a rate for non-publisher {pub!r}", "topics")
                if not _finite_nonneg(hz):
                    raise InputError(f"topic {topic.name!r} has invalid rate {hz!r} for {pub!r}", "topics")
            for member in (*topic.publishers, *topic.subscribers):
                if member not in self.nodes:
                    raise InputError(f"topic {topic.name!r} names unknown ROS node {member!r}", "topics")

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> RosGraph:
        """Parse a ``continuum.rosgraph/v1`` document."""
        if not isinstance(data, Mapping):
            raise InputError("a ROS graph document must be a JSON object")
        fmt = data.get("format", FORMAT)
        if fmt != FORMAT:
            raise InputError(f"unsupported format {fmt!r}, expected {FORMAT!r}", "format")
        raw_nodes = data.get("nodes", [])
        if not isinstance(raw_nodes, list):
            raise InputError("'nodes' must be a list", "nodes")
        raw_topics = data.get("topics", [])
        if not isinstance(raw_topics, list):
            raise InputError("'topics' must be a list", "topics")
        nodes = [_parse_node(i, raw) for i, raw in enumerate(raw_nodes)]
        topics = [_parse_topic(i, raw) for i, raw in enumerate(raw_topics)]
        if not nodes and not topics:
            raise InputError("a ROS graph needs at least one node or topic", "nodes")
        packages = data.get("packages") or {}
        if not isinstance(packages, Mapping):
            raise InputError("'packages' must map package names to {size_mib, archs}", "packages")
        return cls.build(
            str(data.get("name") or "rosgraph"),
            nodes,
            topics,
            packages={str(k): _parse_package(str(k), v) for k, v in packages.items()},
            meta=_mapping(data.get("meta"), "meta", "meta"),
        )

    def to_dict(self) -> dict[str, Any]:
        nodes = []
        for n in self.nodes.values():
            item: dict[str, Any] = {"name": n.name}
            if n.level:
                item["level"] = n.level
            for key in ("context", "origin"):
                if getattr(n, key):
                    item[key] = getattr(n, key)
            if n.cpu:
                item["cpu"] = n.cpu
            if n.memory_mib:
                item["memory_mib"] = n.memory_mib
            if n.packages:
                item["packages"] = list(n.packages)
            if n.pin:
                item["pin"] = n.pin
            _put_measured(item, n.measured, n.why_unmeasured)
            nodes.append(item)
        topics = []
        for t in self.topics.values():
            item = {
                "name": t.name,
                "publishers": list(t.publishers),
                "subscribers": list(t.subscribers),
                "msg_bytes": t.msg_bytes,
            }
            distinct = set(t.rates.values())
            if len(distinct) <= 1 and len(t.rates) == len(t.publishers):
                item["rate_hz"] = next(iter(distinct), 0.0)
            else:
                item["publisher_rates_hz"] = dict(t.rates)
            if t.msg_type:
                item["msg_type"] = t.msg_type
            _put_measured(item, t.measured, t.why_unmeasured)
            topics.append(item)
        doc: dict[str, Any] = {"format": FORMAT, "name": self.name, "nodes": nodes, "topics": topics}
        if self.packages:
            doc["packages"] = self.packages
        if self.meta:
            doc["meta"] = self.meta
        return doc

    # ---- bandwidth (Eq. 3.12) -------------------------------------------------------------------
    def directed_traffic(self) -> dict[tuple[str, str], dict[str, float]]:
        """(publisher, subscriber) -> {topic: bytes/s}: every flow of data between two ROS nodes."""
        flows: dict[tuple[str, str], dict[str, float]] = {}
        for t in self.topics.values():
            for p in t.publishers:
                bps = t.rate(p) * t.msg_bytes
                for s in t.subscribers:
                    if s != p:
                        per_topic = flows.setdefault((p, s), {})
                        per_topic[t.name] = per_topic.get(t.name, 0.0) + bps
        return flows

    def weights(self, mode: str = "per_topic") -> dict[tuple[str, str], float]:
        """Undirected edge weights (bytes/s) keyed by :func:`pair`: Eq. (3.12) summed over shared topics.

        A pair appears when the two nodes share at least one topic, even if its weight is 0.
        """
        if mode not in MODES:
            raise InputError(f"unknown bandwidth mode {mode!r} (one of {', '.join(MODES)})")
        total: dict[tuple[str, str], float] = {}
        shared: dict[tuple[str, str], set[str]] = {}
        for (p, s), per_topic in self.directed_traffic().items():
            key = pair(p, s)
            total[key] = total.get(key, 0.0) + sum(per_topic.values())
            shared.setdefault(key, set()).update(per_topic)
        if mode == "literal":
            # n_topics * m * M_size / T with m the messages of all shared topics and M_size their mean size.
            return {k: len(shared[k]) * w for k, w in total.items()}
        return total

    def bandwidth(self, a: str, b: str, mode: str = "per_topic") -> float:
        """Bytes/s exchanged between ROS nodes ``a`` and ``b`` (both directions)."""
        for name in (a, b):
            if name not in self.nodes:
                raise InputError(f"unknown ROS node {name!r}")
        return self.weights(mode).get(pair(a, b), 0.0)

    def shared_topics(self, a: str, b: str) -> list[str]:
        names = []
        for t in self.topics.values():
            if (a in t.publishers and b in t.subscribers) or (b in t.publishers and a in t.subscribers):
                names.append(t.name)
        return names

    def upstream(self) -> dict[str, set[str]]:
        """ROS node -> the distinct ROS nodes it receives data from."""
        up: dict[str, set[str]] = {n: set() for n in self.nodes}
        for t in self.topics.values():
            for s in t.subscribers:
                up[s].update(p for p in t.publishers if p != s)
        return up

    def downstream(self) -> dict[str, set[str]]:
        down: dict[str, set[str]] = {n: set() for n in self.nodes}
        for t in self.topics.values():
            for p in t.publishers:
                down[p].update(s for s in t.subscribers if s != p)
        return down

    # ---- levels (Fig. 3.19) ---------------------------------------------------------------------
    def levels(self) -> dict[str, str]:
        """Each ROS node's abstraction level: the given one, else :func:`propose_levels`' proposal."""
        proposed = propose_levels(self)
        return {n: node.level or proposed[n] for n, node in self.nodes.items()}

    def to_networkx(self, mode: str = "per_topic"):
        import networkx as nx

        g = nx.Graph(name=self.name)
        for n in sorted(self.nodes, key=natural_key):
            g.add_node(n)
        for (a, b), w in self.weights(mode).items():
            g.add_edge(a, b, weight=w)
        return g

    def __len__(self) -> int:
        return len(self.nodes)


def propose_levels(graph: RosGraph) -> dict[str, str]:
    """Propose a Fig. 3.19 level for every ROS node from the dataflow alone (given levels are ignored here).

    Heuristic (ours; the thesis assigns levels by hand):

    1. ``driver`` -- a source or a sink of the dataflow (publishes nothing or subscribes to nothing): the
       node that talks to hardware or to the simulator sits at the graph's boundary.
    2. ``mission`` -- among the remaining nodes, the one receiving data from the most distinct nodes, when
       that is at least 3: the mission layer orchestrates by aggregating every lower level's results.
       Ties go to the natural-order first name; at most one mission node is proposed.
    3. ``macro`` -- the remaining nodes that fuse data from 2 or more distinct nodes (planners,
       localisation, mapping aggregate lower results).
    4. ``functionality`` -- the rest: they transform one stream (driver data or a command).

    On the Autoware reference system this names the 6 sensors and 2 command sinks drivers, the
    BehaviorPlanner (6 inputs) mission, the fusion nodes macro and the single-input transforms functionality.
    """
    up, down = graph.upstream(), graph.downstream()
    levels: dict[str, str] = {}
    rest = []
    for name in sorted(graph.nodes, key=natural_key):
        if not up[name] or not down[name]:
            levels[name] = "driver"
        else:
            rest.append(name)
    best = max((len(up[n]) for n in rest), default=0)
    if best >= 3:
        levels[next(n for n in rest if len(up[n]) == best)] = "mission"
    for name in rest:
        if name not in levels:
            levels[name] = "macro" if len(up[name]) >= 2 else "functionality"
    return levels


# ---- readers ------------------------------------------------------------------------------------
READERS = ("rosgraph", "autoware", "irobot", "dot")


def load_rosgraph(text: str, fmt: str | None = None, name: str = "", **params: Any) -> RosGraph:
    """Read a ROS graph in any supported format (``fmt`` one of :data:`READERS`; guessed when ``None``).

    ``params`` go to the reader (e.g. ``default_rate_hz``/``default_msg_bytes`` for DOT files).
    """
    if fmt is not None and fmt not in READERS:
        raise InputError(f"unknown ROS graph format {fmt!r} (one of {', '.join(READERS)})", "format")
    check_text_file(text)
    stripped = text.lstrip()
    if fmt == "dot" or (fmt is None and not stripped.startswith(("{", "["))):
        return from_dot(text, name=name, **params)
    doc = loads_json(text)
    fmt = fmt or guess_json_format(doc)
    if fmt == "autoware":
        return from_autoware(doc, **params)
    if fmt == "irobot":
        return from_irobot(doc, name=name, **params)
    graph = RosGraph.from_dict(doc)
    if name and not doc.get("name"):
        graph.name = name
    return graph


def guess_json_format(doc: Any) -> str:
    if not isinstance(doc, Mapping):
        raise InputError("a ROS graph document must be a JSON object")
    if doc.get("format") == FORMAT or "topics" in doc:
        return "rosgraph"
    nodes = doc.get("nodes")
    if isinstance(nodes, list) and nodes and isinstance(nodes[0], Mapping):
        if "node_name" in nodes[0]:
            return "irobot"
        if "publishes" in nodes[0] or "subscribes" in nodes[0]:
            return "autoware"
    if "format" in doc:
        raise InputError(f"unsupported format {doc['format']!r}, expected {FORMAT!r}", "format")
    raise InputError(
        "cannot tell the ROS graph format: expected a continuum.rosgraph/v1 document ('topics'), an Autoware "
        "reference system ('nodes' with 'publishes'/'subscribes') or an iRobot topology ('nodes' with 'node_name')"
    )


# -- Autoware reference system (ros-realtime/reference-system, as extracted in datasets/ros2) --------
def from_autoware(doc: Mapping[str, Any]) -> RosGraph:
    """Read the Autoware reference system JSON: ``nodes[]`` with ``publishes``/``subscribes``/callbacks and
    ``edges[]`` with ``from, to, topic, msg_bytes``.

    Publishing rates follow the reference system's node semantics: a timer callback publishes every
    ``period_ms``; a subscription callback publishes at its input topic's rate; a fusion callback ("publishes
    only when both inputs present") publishes at the rate of its slowest input. Rates propagate along the
    dataflow until they settle. A node's CPU demand is the sum over callbacks of ``runtime_ms * rate`` (its
    callbacks' own work; :mod:`~.resource_model` adds the middleware's share). Nodes of type ``sensor`` or
    ``command`` (the dataset's hardware-facing nodes: lidar and map sensors, the vehicle's drive-by-wire sink)
    get the level ``driver``; the other levels are proposed from the structure.
    """
    raw_nodes = doc.get("nodes")
    if not isinstance(raw_nodes, list) or not raw_nodes:
        raise InputError("an Autoware graph needs a non-empty 'nodes' list", "nodes")
    specs: dict[str, Mapping[str, Any]] = {}
    for i, raw in enumerate(raw_nodes):
        if not isinstance(raw, Mapping) or not isinstance(raw.get("name"), str) or not raw["name"]:
            raise InputError(f"nodes[{i}] needs a string 'name'", "nodes")
        for key in ("publishes", "subscribes"):
            _topic_names(raw.get(key), f"node {raw['name']!r}: '{key}'")
        if raw["name"] in specs:
            raise InputError(f"duplicate ROS node name {raw['name']!r}", "nodes")
        specs[raw["name"]] = raw
    sizes: dict[str, float] = {}
    for i, e in enumerate(_list(doc.get("edges"), "edges", "edges")):
        if not isinstance(e, Mapping) or not isinstance(e.get("topic"), str):
            raise InputError(f"edges[{i}] needs a 'topic'", "edges")
        size = e.get("msg_bytes", 0)
        if not _finite_nonneg(size):
            raise InputError(f"edges[{i}] (topic {e['topic']!r}) has invalid msg_bytes {size!r}", "edges")
        sizes[e["topic"]] = float(size)
    callbacks = {n: _autoware_callbacks(n, spec) for n, spec in specs.items()}
    rates = _propagate_rates(callbacks)
    publishers: dict[str, list[str]] = {}
    subscribers: dict[str, list[str]] = {}
    for n, spec in specs.items():
        for t in spec.get("publishes") or []:
            publishers.setdefault(t, []).append(n)
        for t in spec.get("subscribes") or []:
            subscribers.setdefault(t, []).append(n)
    topics = []
    for t in sorted(set(publishers) | set(subscribers), key=natural_key):
        pubs = tuple(publishers.get(t, ()))
        topics.append(
            Topic(t, pubs, tuple(subscribers.get(t, ())), {p: rates.get(t, 0.0) for p in pubs}, sizes.get(t, 0.0))
        )
    nodes = []
    for n, spec in specs.items():
        cpu = 0.0
        for cb in callbacks[n]:
            rt = cb.get("runtime_ms", spec.get("runtime_ms", 0.0)) or 0.0
            if not _finite_nonneg(rt):
                raise InputError(f"node {n!r} has invalid runtime_ms {rt!r:.40}", "nodes")
            cpu += float(rt) * _trigger_rate(cb, rates) / 1000.0
        # The dataset marks the nodes that talk to hardware by type (sensors, vehicle commands): drivers.
        level = "driver" if spec.get("type") in AUTOWARE_DRIVER_TYPES else None
        nodes.append(RosNode(n, level=level, cpu=cpu))
    meta = {
        "source": doc.get("source"),
        "reader": "autoware",
        "topic_rates_hz": rates,
        "node_types": {n: spec.get("type", "") for n, spec in specs.items()},
    }
    return RosGraph.build(str(doc.get("name") or "autoware_reference_system"), nodes, topics, meta=meta)


def _autoware_callbacks(name: str, spec: Mapping[str, Any]) -> list[dict[str, Any]]:
    raw = spec.get("callbacks")
    if isinstance(raw, list) and raw:
        out = []
        for i, cb in enumerate(raw):
            if not isinstance(cb, Mapping) or cb.get("kind") not in ("timer", "subscription"):
                raise InputError(f"node {name!r} callbacks[{i}] needs kind 'timer' or 'subscription'", "nodes")
            if cb["kind"] == "timer" and not _positive(cb.get("period_ms")):
                raise InputError(f"node {name!r} callbacks[{i}] has no positive 'period_ms'", "nodes")
            _topic_names(cb.get("publishes"), f"node {name!r} callbacks[{i}].publishes")
            if cb["kind"] == "subscription" and not isinstance(cb.get("topic", ""), str):
                raise InputError(f"node {name!r} callbacks[{i}].topic must be a topic name", "nodes")
            out.append(dict(cb))
        return out
    # No callback detail: a node with a period is a timer, otherwise it republishes per input message
    # (a node with several inputs waits for all of them, like the reference system's fusion nodes).
    pubs = _topic_names(spec.get("publishes"), f"node {name!r} publishes")
    if spec.get("period_ms") is not None:
        if not _positive(spec.get("period_ms")):
            raise InputError(f"node {name!r} has invalid period_ms {spec.get('period_ms')!r}", "nodes")
        return [{"kind": "timer", "period_ms": spec["period_ms"], "publishes": pubs}]
    subs = _topic_names(spec.get("subscribes"), f"node {name!r} subscribes")
    note = "publishes only when both inputs present" if len(subs) > 1 else ""
    return [{"kind": "subscription", "topic": t, "publishes": pubs, "note": note} for t in subs]


def _trigger_rate(cb: Mapping[str, Any], rates: Mapping[str, float]) -> float:
    if cb["kind"] == "timer":
        return 1000.0 / float(cb["period_ms"])
    return rates.get(cb.get("topic", ""), 0.0)


def _waits_for_all(cb: Mapping[str, Any]) -> bool:
    return "both inputs" in str(cb.get("note", "")) or "all inputs" in str(cb.get("note", ""))


def _propagate_rates(callbacks: Mapping[str, list[dict[str, Any]]]) -> dict[str, float]:
    """Topic -> publish rate (Hz), iterated to a fixed point (timers break dataflow cycles)."""
    producers: dict[str, list[dict[str, Any]]] = {}
    for cbs in callbacks.values():
        for cb in cbs:
            for t in cb.get("publishes", []):
                producers.setdefault(t, []).append(cb)
    rates = dict.fromkeys(producers, 0.0)
    for _ in range(len(producers) + 2):
        changed = False
        for t, cbs in producers.items():
            fused = [cb for cb in cbs if _waits_for_all(cb)]
            plain = [cb for cb in cbs if not _waits_for_all(cb)]
            value = sum(_trigger_rate(cb, rates) for cb in plain)
            if fused:
                value += min(_trigger_rate(cb, rates) for cb in fused)
            if not math.isclose(value, rates[t], rel_tol=1e-12, abs_tol=1e-12):
                rates[t], changed = value, True
        if not changed:
            break
    return rates


# -- iRobot ros2-performance topology ---------------------------------------------------------------
#: Payload bytes of the scalar types used in ros2-performance's ``stampedN_<type>`` messages.
_SCALAR_BYTES = {
    "int8": 1, "uint8": 1, "byte": 1, "char": 1, "bool": 1,
    "int16": 2, "uint16": 2, "int32": 4, "uint32": 4, "float32": 4,
    "int64": 8, "uint64": 8, "float64": 8,
}  # fmt: skip
#: ``performance_test_msgs/PerformanceHeader``: builtin_interfaces/Time (8) + 3 x 4-byte fields.
IROBOT_HEADER_BYTES = 20
_UNITS = {"b": 1, "kb": 1024, "mb": 1024 * 1024}


def irobot_msg_bytes(msg_type: str, msg_size: Any = None) -> float | None:
    """Serialized payload size of a ros2-performance message type, or ``None`` if it is not known.

    ``stamped_vector`` carries ``msg_size`` bytes; ``stampedN_<scalar>`` carries N scalars;
    ``stamped<k>kb``/``mb``/``b`` carry k KiB/MiB/bytes; all add the 20-byte PerformanceHeader.
    A ``msg_size`` given with any type wins over the type's nominal size.
    """
    if msg_size is not None:
        if not _finite_nonneg(msg_size):
            return None
        return IROBOT_HEADER_BYTES + float(msg_size)
    t = msg_type.lower()
    m = re.fullmatch(r"stamped(\d*)_([a-z]+\d*)", t)
    if m and m.group(2) in _SCALAR_BYTES:
        return IROBOT_HEADER_BYTES + int(m.group(1) or 1) * _SCALAR_BYTES[m.group(2)]
    m = re.fullmatch(r"stamped(\d+)(b|kb|mb)", t)
    if m:
        return IROBOT_HEADER_BYTES + int(m.group(1)) * _UNITS[m.group(2)]
    return None


def from_irobot(doc: Mapping[str, Any], name: str = "") -> RosGraph:
    """Read an iRobot ``ros2-performance`` topology: ``nodes[]`` with ``node_name``, ``publishers[]``
    (``topic_name, msg_type, period_ms`` or ``freq_hz``, optional ``msg_size``) and ``subscribers[]``.

    Services and clients are ignored (request/response traffic has no publishing rate in these files).
    """
    raw_nodes = doc.get("nodes")
    if not isinstance(raw_nodes, list) or not raw_nodes:
        raise InputError("an iRobot topology needs a non-empty 'nodes' list", "nodes")
    nodes: list[RosNode] = []
    pubs: dict[str, list[str]] = {}
    subs: dict[str, list[str]] = {}
    rates: dict[str, dict[str, float]] = {}
    sizes: dict[str, float] = {}
    types: dict[str, str] = {}
    for i, raw in enumerate(raw_nodes):
        if not isinstance(raw, Mapping) or not isinstance(raw.get("node_name"), str) or not raw["node_name"]:
            raise InputError(f"nodes[{i}] needs a string 'node_name'", "nodes")
        node = raw["node_name"]
        nodes.append(RosNode(node))
        for j, p in enumerate(_list(raw.get("publishers"), f"node {node!r} publishers", "nodes")):
            where = f"node {node!r} publishers[{j}]"
            topic = _irobot_topic(p, where)
            hz = _irobot_rate(p, where)
            size = irobot_msg_bytes(str(p.get("msg_type", "")), p.get("msg_size"))
            if size is None:
                raise InputError(
                    f"{where} (topic {topic!r}): unknown msg_type {p.get('msg_type')!r}; give 'msg_size' in bytes",
                    "nodes",
                )
            if topic in sizes and sizes[topic] != size:
                raise InputError(f"{where}: topic {topic!r} published with two message sizes", "nodes")
            pubs.setdefault(topic, []).append(node)
            rates.setdefault(topic, {})[node] = rates.get(topic, {}).get(node, 0.0) + hz
            sizes[topic], types[topic] = size, str(p.get("msg_type", ""))
        for j, s in enumerate(_list(raw.get("subscribers"), f"node {node!r} subscribers", "nodes")):
            topic = _irobot_topic(s, f"node {node!r} subscribers[{j}]")
            subs.setdefault(topic, []).append(node)
            if topic not in sizes and s.get("msg_type"):
                guess = irobot_msg_bytes(str(s["msg_type"]), s.get("msg_size"))
                if guess is not None:
                    sizes[topic], types[topic] = guess, str(s["msg_type"])
    topics = [
        Topic(
            t,
            tuple(dict.fromkeys(pubs.get(t, []))),
            tuple(dict.fromkeys(subs.get(t, []))),
            rates.get(t, {}),
            sizes.get(t, 0.0),
            types.get(t, ""),
        )
        for t in sorted(set(pubs) | set(subs), key=natural_key)
    ]
    return RosGraph.build(name or str(doc.get("name") or "irobot_topology"), nodes, topics, meta={"reader": "irobot"})


def _irobot_topic(raw: Any, where: str) -> str:
    if not isinstance(raw, Mapping) or not isinstance(raw.get("topic_name"), str) or not raw["topic_name"]:
        raise InputError(f"{where} needs a string 'topic_name'", "nodes")
    return raw["topic_name"]


def _irobot_rate(raw: Mapping[str, Any], where: str) -> float:
    if raw.get("freq_hz") is not None:
        if not _positive(raw["freq_hz"]):
            raise InputError(f"{where} has invalid freq_hz {raw['freq_hz']!r}", "nodes")
        return float(raw["freq_hz"])
    if raw.get("period_ms") is not None:
        if not _positive(raw["period_ms"]):
            raise InputError(f"{where} has invalid period_ms {raw['period_ms']!r}", "nodes")
        return 1000.0 / float(raw["period_ms"])
    raise InputError(f"{where} needs 'period_ms' or 'freq_hz'", "nodes")


# -- Graphviz DOT (rqt_graph export) ---------------------------------------------------------------
def from_dot(text: str, name: str = "", default_rate_hz: float = 1.0, default_msg_bytes: float = 1.0) -> RosGraph:
    """Read a DOT graph as rqt_graph exports it (or any digraph of ROS nodes).

    * A vertex is a topic when its URL starts with ``topic:`` or, in a graph whose ids all follow rqt_graph's
      ``n_<node>``/``t_<topic>`` convention, its id starts with ``t_`` (rqt_graph's "Nodes/Topics" modes);
      otherwise it is a ROS node. Shapes are not used: hand-drawn graphs (the Autoware one) draw nodes as
      boxes too. Names are the ``label`` when given (rqt_graph's ``n_/talker`` is labelled ``/talker``).
    * An edge node -> topic is a publication, topic -> node a subscription. An edge node -> node (rqt_graph's
      "Nodes only" mode) is a publication of the topic on its label's first line; unlabelled, the topic is
      named after the publisher (as in the Autoware reference system, where each node publishes one topic).
    * Invisible edges (``style=invis``) are layout aids and are ignored.
    * Rates: a label line like ``10.0 Hz`` (rqt_graph's statistics) gives the rate; an edge attribute
      ``rate_hz``/``msg_bytes`` is honoured; otherwise ``default_rate_hz`` and ``default_msg_bytes`` apply, so
      weights count messages per second per topic.
    """
    parsed = parse_dot(text)
    vertices, edges = parsed["nodes"], parsed["edges"]

    def display(vid: str) -> str:
        label = vertices.get(vid, {}).get("label")
        if label and label != "\\N":
            return _dot_label_lines(label)[0]
        return vid

    # rqt_graph names ROS nodes "n_<name>" and topics "t_<name>"; only trust the prefix when every id uses it.
    rqt_ids = bool(vertices) and all(v.startswith(("n_", "t_")) for v in vertices)

    def is_topic(vid: str) -> bool:
        url = vertices.get(vid, {}).get("URL", vertices.get(vid, {}).get("url", ""))
        return url.startswith("topic:") or (rqt_ids and vid.startswith("t_"))

    nodes = {display(v): RosNode(display(v)) for v in vertices if not is_topic(v)}
    pubs: dict[str, list[str]] = {}
    subs: dict[str, list[str]] = {}
    rates: dict[str, dict[str, float]] = {}
    sizes: dict[str, float] = {}
    for e in edges:
        attrs = e["attrs"]
        if "invis" in attrs.get("style", ""):
            continue
        src, dst, line = e["src"], e["dst"], e["line"]
        rate, size = _dot_edge_rate(attrs, default_rate_hz, line), _dot_edge_size(attrs, default_msg_bytes, line)
        if is_topic(src) and is_topic(dst):
            raise InputError(f"line {line}: edge {src!r} -> {dst!r} joins two topics", "dot")
        if is_topic(dst):
            topic, publisher, subscriber = display(dst), display(src), None
        elif is_topic(src):
            topic, publisher, subscriber = display(src), None, display(dst)
        else:
            label = attrs.get("label")
            topic = _dot_label_lines(label)[0] if label else display(src)
            publisher, subscriber = display(src), display(dst)
        if publisher is not None:
            if publisher not in pubs.setdefault(topic, []):
                pubs[topic].append(publisher)
            rates.setdefault(topic, {})[publisher] = max(rates.get(topic, {}).get(publisher, 0.0), rate)
        if subscriber is not None and subscriber not in subs.setdefault(topic, []):
            subs[topic].append(subscriber)
        sizes[topic] = max(sizes.get(topic, 0.0), size)
    topics = [
        Topic(t, tuple(pubs.get(t, ())), tuple(subs.get(t, ())), rates.get(t, {}), sizes.get(t, default_msg_bytes))
        for t in sorted(set(pubs) | set(subs), key=natural_key)
    ]
    return RosGraph.build(
        name or parsed["name"] or "dot", nodes.values(), topics, meta={"reader": "dot", "directed": parsed["directed"]}
    )


def _dot_label_lines(label: str) -> list[str]:
    return [s.strip() for s in re.split(r"\\n|\\l|\\r|\n", label) if s.strip()] or [""]


def _dot_edge_rate(attrs: Mapping[str, str], default: float, line: int) -> float:
    if "rate_hz" in attrs:
        return _dot_number(attrs["rate_hz"], "rate_hz", line)
    for part in _dot_label_lines(attrs.get("label", ""))[1:]:
        m = re.search(r"([0-9]*\.?[0-9]+)\s*Hz", part)
        if m:
            return float(m.group(1))
    return default


def _dot_edge_size(attrs: Mapping[str, str], default: float, line: int) -> float:
    return _dot_number(attrs["msg_bytes"], "msg_bytes", line) if "msg_bytes" in attrs else default


def _dot_number(text: str, what: str, line: int) -> float:
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not (math.isfinite(value) and value >= 0):
        raise InputError(f"line {line}: invalid {what} {text!r}", "dot")
    return value


_DOT_TOKEN = re.compile(
    r"""(?P<ws>[ \t\r\f\v]+)
      | (?P<nl>\n)
      | (?P<comment>//[^\n]*|/\*.*?\*/)
      | (?P<string>"(?:[^"\\]|\\.)*")
      | (?P<edgeop>->|--)
      | (?P<id>[A-Za-z_\x80-\uffff][A-Za-z_0-9\x80-\uffff]*|-?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?))
      | (?P<punct>[{}\[\];,=:])
      | (?P<html><)
    """,
    re.VERBOSE | re.DOTALL,
)


def _dot_tokens(text: str) -> list[tuple[str, str, int]]:
    """(kind, value, line) tokens; '#' preprocessor lines and comments are dropped."""
    tokens: list[tuple[str, str, int]] = []
    pos, line = 0, 1
    at_line_start = True
    while pos < len(text):
        if at_line_start and text[pos] == "#":
            end = text.find("\n", pos)
            pos = len(text) if end < 0 else end
            continue
        m = _DOT_TOKEN.match(text, pos)
        if not m:
            raise InputError(f"line {line}: unexpected character {text[pos]!r}", "dot")
        kind = m.lastgroup
        value = m.group()
        if kind == "html":
            value, end = _dot_html(text, pos, line)
            tokens.append(("str", value, line))
            line += text.count("\n", pos, end)
            pos = end
            at_line_start = False
            continue
        if kind == "string":
            # Adjacent "a" + "b" concatenation is DOT syntax too.
            tokens.append(("str", value[1:-1].replace('\\"', '"'), line))
        elif kind in ("id", "edgeop", "punct"):
            tokens.append((kind, value, line))
        line += value.count("\n")
        at_line_start = kind == "nl" or (at_line_start and kind == "ws")
        pos = m.end()
    tokens.append(("eof", "", line))
    return tokens


def _dot_html(text: str, pos: int, line: int) -> tuple[str, int]:
    depth, i = 0, pos
    while i < len(text):
        if text[i] == "<":
            depth += 1
        elif text[i] == ">":
            depth -= 1
            if depth == 0:
                return text[pos + 1 : i], i + 1
        i += 1
    raise InputError(f"line {line}: unterminated HTML string", "dot")


class _DotParser:
    """Recursive-descent parser of the DOT grammar (graphviz.org/doc/info/lang.html)."""

    KEYWORDS = ("strict", "graph", "digraph", "subgraph", "node", "edge")

    def __init__(self, text: str):
        self.tokens = _dot_tokens(text)
        self.i = 0
        self.nodes: dict[str, dict[str, str]] = {}
        self.edges: list[dict[str, Any]] = []

    # token helpers
    def peek(self, k: int = 0) -> tuple[str, str, int]:
        return self.tokens[min(self.i + k, len(self.tokens) - 1)]

    def next(self) -> tuple[str, str, int]:
        tok = self.peek()
        self.i += 1
        return tok

    def is_kw(self, tok: tuple[str, str, int], word: str) -> bool:
        return tok[0] == "id" and tok[1].lower() == word

    def expect(self, kind: str, value: str | None = None) -> tuple[str, str, int]:
        """The next token, which must be of ``kind`` ("id" also accepts quoted and HTML strings)."""
        tok = self.next()
        kind_ok = tok[0] in ("id", "str") if kind == "id" else tok[0] == kind
        if not kind_ok or (value is not None and tok[1] != value):
            want = value or kind
            got = tok[1] or "end of file"
            raise InputError(f"line {tok[2]}: expected {want!r}, got {got!r}", "dot")
        return tok

    # grammar
    def parse(self) -> dict[str, Any]:
        if self.is_kw(self.peek(), "strict"):
            self.next()
        head = self.next()
        if not (self.is_kw(head, "graph") or self.is_kw(head, "digraph")):
            raise InputError(f"line {head[2]}: expected 'graph' or 'digraph', got {head[1] or 'end of file'!r}", "dot")
        self.directed = head[1].lower() == "digraph"
        name = ""
        if self.peek()[0] in ("id", "str"):
            name = self.next()[1]
        self.expect("punct", "{")
        self.stmt_list({}, {})
        self.expect("punct", "}")
        tail = self.peek()
        if tail[0] != "eof":
            raise InputError(f"line {tail[2]}: unexpected {tail[1]!r} after the graph's closing brace", "dot")
        return {"name": name, "directed": self.directed, "nodes": self.nodes, "edges": self.edges}

    def stmt_list(self, node_defaults: dict[str, str], edge_defaults: dict[str, str]) -> list[str]:
        """Parse statements until '}'; return the node ids mentioned (for edges to subgraphs)."""
        node_defaults, edge_defaults = dict(node_defaults), dict(edge_defaults)
        members: list[str] = []
        while True:
            tok = self.peek()
            if tok[0] == "eof":
                raise InputError(f"line {tok[2]}: missing '}}'", "dot")
            if tok == ("punct", "}", tok[2]):
                return members
            if tok[0] == "punct" and tok[1] == ";":
                self.next()
                continue
            if self.is_kw(tok, "node") or self.is_kw(tok, "edge") or self.is_kw(tok, "graph"):
                self.next()
                attrs = self.attr_lists()
                if tok[1].lower() == "node":
                    node_defaults.update(attrs)
                elif tok[1].lower() == "edge":
                    edge_defaults.update(attrs)
                continue
            if tok[0] in ("id", "str") and self.peek(1)[:2] == ("punct", "=") and not self.is_kw(tok, "subgraph"):
                self.next()
                self.next()
                self.expect("id")  # graph attribute: ignored
                continue
            members.extend(self.edge_or_node(node_defaults, edge_defaults))

    def operand(self, node_defaults: dict[str, str], edge_defaults: dict[str, str]) -> tuple[list[str], bool, int]:
        tok = self.peek()
        if self.is_kw(tok, "subgraph") or tok[:2] == ("punct", "{"):
            if self.is_kw(tok, "subgraph"):
                self.next()
                if self.peek()[0] in ("id", "str"):
                    self.next()
            self.expect("punct", "{")
            ids = self.stmt_list(node_defaults, edge_defaults)
            self.expect("punct", "}")
            return ids, True, tok[2]
        if tok[0] == "str":
            pass  # a quoted id is never a keyword: "node" -> "edge" is fine
        elif tok[0] != "id" or tok[1].lower() in self.KEYWORDS:
            raise InputError(f"line {tok[2]}: expected a node id, got {tok[1] or 'end of file'!r}", "dot")
        self.next()
        if self.peek()[:2] == ("punct", ":"):  # port (and compass point): irrelevant here
            self.next()
            self.expect("id")
            if self.peek()[:2] == ("punct", ":"):
                self.next()
                self.expect("id")
        return [tok[1]], False, tok[2]

    def edge_or_node(self, node_defaults: dict[str, str], edge_defaults: dict[str, str]) -> list[str]:
        chain = [self.operand(node_defaults, edge_defaults)]
        while self.peek()[0] == "edgeop":
            op = self.next()
            if (op[1] == "->") != self.directed:
                kind = "digraph" if self.directed else "graph"
                raise InputError(f"line {op[2]}: edge operator {op[1]!r} in a {kind}", "dot")
            chain.append(self.operand(node_defaults, edge_defaults))
        attrs = self.attr_lists() if self.peek()[:2] == ("punct", "[") else {}
        mentioned: list[str] = []
        for ids, is_sub, _ in chain:
            for vid in ids:
                if vid not in self.nodes:
                    self.nodes[vid] = dict(node_defaults)
                if not is_sub and len(chain) == 1:
                    self.nodes[vid].update(attrs)
            mentioned.extend(ids)
        for (a, _, line), (b, _, _) in itertools.pairwise(chain):
            for src in a:
                for dst in b:
                    self.edges.append({"src": src, "dst": dst, "attrs": {**edge_defaults, **attrs}, "line": line})
        return mentioned

    def attr_lists(self) -> dict[str, str]:
        attrs: dict[str, str] = {}
        while self.peek()[:2] == ("punct", "["):
            self.next()
            while self.peek()[:2] != ("punct", "]"):
                key = self.expect("id")[1]
                value = "true"
                if self.peek()[:2] == ("punct", "="):
                    self.next()
                    value = self.expect("id")[1]
                attrs[key] = value
                if self.peek()[0] == "punct" and self.peek()[1] in ",;":
                    self.next()
            self.next()
        return attrs


def parse_dot(text: str) -> dict[str, Any]:
    """Parse DOT text into ``{"name", "directed", "nodes": {id: attrs}, "edges": [{src, dst, attrs, line}]}``."""
    return _DotParser(text).parse()


# ---- contract parsing helpers -------------------------------------------------------------------
def _finite_nonneg(x: Any) -> TypeGuard[int | float]:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and x >= 0


def _positive(x: Any) -> TypeGuard[int | float]:
    return _finite_nonneg(x) and x > 0


def _parse_level(where: str, raw: Any) -> str | None:
    if raw is None or raw == "":
        return None
    if not isinstance(raw, str):
        raise InputError(f"{where} has a non-string level {raw!r}", "nodes")
    level = LEVEL_ALIASES.get(raw.lower(), raw.lower())
    if level not in LEVELS:
        raise InputError(f"{where} has unknown level {raw!r} (one of {', '.join(LEVELS)})", "nodes")
    return level


def _put_measured(item: dict[str, Any], measured: bool | None, why: str) -> None:
    if measured is not None:
        item["measured"] = measured
    if why:
        item["why_unmeasured"] = why


def _parse_measured(where: str, raw: Mapping[str, Any], field: str) -> tuple[bool | None, str]:
    """``measured`` (a boolean, optional) and ``why_unmeasured`` (a short text) of a captured node or topic."""
    measured = raw.get("measured")
    if measured is not None and not isinstance(measured, bool):
        raise InputError(f"{where}: 'measured' must be true or false", field)
    why = raw.get("why_unmeasured", "")
    if why is None:
        why = ""
    if not isinstance(why, str) or len(why) > 1000 or "\x00" in why:
        raise InputError(f"{where}: 'why_unmeasured' must be a text of at most 1000 characters", field)
    return measured, why


def _parse_node(index: int, raw: Any) -> RosNode:
    if not isinstance(raw, Mapping):
        raise InputError(f"nodes[{index}] must be an object", "nodes")
    name = raw.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"nodes[{index}] has no string 'name'", "nodes")
    where = f"ROS node {name!r}"
    values = {}
    for key in ("cpu", "memory_mib"):
        value = raw.get(key, 0.0)
        if not _finite_nonneg(value):
            raise InputError(f"{where} has invalid {key} {value!r}", "nodes")
        values[key] = float(value)
    packages = raw.get("packages", [])
    if not isinstance(packages, list) or not all(isinstance(p, str) and p for p in packages):
        raise InputError(f"{where}: 'packages' must be a list of package names", "nodes")
    for p in packages:  # they are written into Dockerfiles (image_inheritance): the grammar, checked here
        check_package(p, "nodes", f"{where}: package")
    pin = raw.get("pin")
    if pin in ("", None):
        pin = None
    elif pin not in PINS:
        raise InputError(f"{where} has unknown pin {pin!r} (one of {', '.join(PINS)}, or none)", "nodes")
    measured, why = _parse_measured(where, raw, "nodes")
    return RosNode(
        name,
        measured=measured,
        why_unmeasured=why,
        pin=pin,
        level=_parse_level(where, raw.get("level")),
        context=str(raw.get("context", "") or ""),
        origin=str(raw.get("origin", "") or ""),
        cpu=values["cpu"],
        memory_mib=values["memory_mib"],
        packages=tuple(dict.fromkeys(packages)),
    )


def _names(where: str, raw: Any, key: str) -> tuple[str, ...]:
    value = raw.get(key, [])
    if not isinstance(value, list):
        raise InputError(f"{where}: '{key}' must be a list of ROS node names", "topics")
    for i, item in enumerate(value):
        if not isinstance(item, str) or not item:
            raise InputError(f"{where}: {key}[{i}] must be a ROS node name, got {item!r}", "topics")
    return tuple(dict.fromkeys(value))


def _parse_topic(index: int, raw: Any) -> Topic:
    if not isinstance(raw, Mapping):
        raise InputError(f"topics[{index}] must be an object", "topics")
    name = raw.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"topics[{index}] has no string 'name'", "topics")
    where = f"topic {name!r}"
    publishers = _names(where, raw, "publishers")
    subscribers = _names(where, raw, "subscribers")
    size = raw.get("msg_bytes", 0.0)
    if not _finite_nonneg(size):
        raise InputError(f"{where} has invalid msg_bytes {size!r}", "topics")
    rates = _topic_rates(where, raw, publishers)
    measured, why = _parse_measured(where, raw, "topics")
    return Topic(name, publishers, subscribers, rates, float(size), str(raw.get("msg_type", "") or ""), measured, why)


def _topic_rates(where: str, raw: Mapping[str, Any], publishers: Sequence[str]) -> dict[str, float]:
    """Per-publisher Hz from ``rate_hz``, ``period_ms``, ``publisher_rates_hz`` or measured
    ``messages`` over ``window_s`` (all publishers together, split evenly among them)."""
    if "publisher_rates_hz" in raw:
        given = raw["publisher_rates_hz"]
        if not isinstance(given, Mapping):
            raise InputError(f"{where}: 'publisher_rates_hz' must map publisher -> Hz", "topics")
        out = {}
        for pub, hz in given.items():
            if not _finite_nonneg(hz):
                raise InputError(f"{where} has invalid rate {hz!r} for publisher {pub!r}", "topics")
            out[str(pub)] = float(hz)
        return out
    if "messages" in raw or "window_s" in raw:
        m, window = raw.get("messages"), raw.get("window_s")
        if not _finite_nonneg(m) or not _positive(window):
            raise InputError(f"{where}: 'messages' needs a non-negative count and 'window_s' a positive time", "topics")
        return {p: m / window / len(publishers) for p in publishers} if publishers else {}
    if "period_ms" in raw:
        if not _positive(raw["period_ms"]):
            raise InputError(f"{where} has invalid period_ms {raw['period_ms']!r}", "topics")
        hz = 1000.0 / raw["period_ms"]
    else:
        hz = raw.get("rate_hz", 0.0)
        if not _finite_nonneg(hz):
            raise InputError(f"{where} has invalid rate_hz {hz!r}", "topics")
    return dict.fromkeys(publishers, float(hz))


def _parse_package(name: str, raw: Any) -> dict[str, Any]:
    check_package(name, "packages")
    if isinstance(raw, (int, float)) and _finite_nonneg(raw):
        return {"size_mib": float(raw)}
    if not isinstance(raw, Mapping):
        raise InputError(f"package {name!r} must be a size in MiB or an object with 'size_mib'", "packages")
    size = raw.get("size_mib", 0.0)
    if not _finite_nonneg(size):
        raise InputError(f"package {name!r} has invalid size_mib {size!r}", "packages")
    out: dict[str, Any] = {"size_mib": float(size)}
    if "archs" in raw:
        archs = raw["archs"]
        if not isinstance(archs, list) or not all(isinstance(a, str) for a in archs):
            raise InputError(f"package {name!r}: 'archs' must be a list of architectures", "packages")
        out["archs"] = list(archs)
    return out


def _list(value: Any, where: str, field: str) -> list:
    """A document's list (absent/null: empty), or an InputError naming it."""
    if value is None:
        return []
    if not isinstance(value, list):
        raise InputError(f"{where} must be a list, not {type(value).__name__}", field)
    return value


def _mapping(value: Any, where: str, field: str) -> dict:
    """A document's object (absent/null: empty), or an InputError naming it."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise InputError(f"{where} must be an object, not {type(value).__name__}", field)
    return dict(value)


def _topic_names(value: Any, where: str) -> list[str]:
    """A list of topic names (absent/null: empty), or an InputError naming it."""
    names = _list(value, where, "nodes")
    if not all(isinstance(t, str) for t in names):
        raise InputError(f"{where} must be a list of topic names (strings)", "nodes")
    return list(names)
