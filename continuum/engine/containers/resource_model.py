"""The CPU and memory a ROS node asks for: the resource profile of thesis Section 3.2.1 (Figs. 3.22-3.23, the
resource tie-breaker) and the container specs of Section 3.3.1 (Table 4.26: CPU cores and memory per
container), estimated from the ROS graph when the node was not profiled.

The thesis profiles ROS nodes at design level L1 but prints no per-node model; the spec (02, 2.6 and 5.1)
only says containers carry CPU cores and memory. Our model (a **proposal**, every constant a parameter of
:class:`ResourceModel`):

* **CPU (cores)** = the node's own work (``RosNode.cpu``: its callbacks' run time x trigger rate, as the
  Autoware reader computes it, or a profiled figure) + a base share for the executor and DDS discovery
  (``base_cores``) + the middleware's share for every message it publishes or takes:
  ``sum over messages/s of (per_message_us + msg_bytes / 1024 * per_kib_us) / 1e6``.
  Publish rates are the topics' per-publisher rates; a subscriber takes every message of every publisher.
* **Memory (MiB)** = ``RosNode.memory_mib`` when it was profiled (non-zero: a measured resident size),
  otherwise the resident size of one ROS 2 process with its DDS participant (``process_mib``) + the message
  queues of its endpoints: ``history_depth`` messages of each topic it publishes or subscribes to
  (KEEP_LAST 10 is the ROS 2 default QoS).

The defaults are stated assumptions, not measurements of ours: 5 millicores of base load, 25 us per message
and 2 us per KiB (serialise, copy and hand to DDS on a desktop-class core), 20 MiB per process, depth 10.
A container's request is the sum over its ROS nodes; the per-container runtime overhead (29 MB Docker,
39 MB K3s, Table 4.17) is added by the placement, not here.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

from continuum.engine.core.errors import InputError

if TYPE_CHECKING:
    from continuum.engine.containers.rosgraph import RosGraph

__all__ = ["NodeProfile", "ResourceModel", "profiles"]

MIB = 1024 * 1024


@dataclass(frozen=True)
class ResourceModel:
    base_cores: float = 0.005
    per_message_us: float = 25.0
    per_kib_us: float = 2.0
    process_mib: float = 20.0
    history_depth: int = 10

    def __post_init__(self) -> None:
        for key, value in asdict(self).items():
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
                raise InputError(f"resource model: {key} must be a non-negative number, got {value!r}", "model")

    @classmethod
    def from_dict(cls, raw: Any) -> ResourceModel:
        if raw is None:
            return cls()
        if not isinstance(raw, dict):
            raise InputError("resource model must be an object", "model")
        unknown = sorted(set(raw) - set(cls.__dataclass_fields__))
        if unknown:
            raise InputError(f"resource model: unknown parameter {unknown[0]!r}", "model")
        return cls(**raw)

    def to_dict(self) -> dict[str, float]:
        return asdict(self)


@dataclass(frozen=True)
class NodeProfile:
    """One ROS node's request and how it was obtained (for the pages' "how was this computed")."""

    cpu: float
    memory_mib: float
    work_cores: float
    middleware_cores: float
    messages_per_s: float
    memory_profiled: bool
    queue_mib: float

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def profiles(graph: RosGraph, model: ResourceModel | None = None) -> dict[str, NodeProfile]:
    """ROS node -> :class:`NodeProfile` under ``model`` (the defaults when ``None``)."""
    model = model or ResourceModel()
    msgs: dict[str, float] = dict.fromkeys(graph.nodes, 0.0)  # messages/s sent + taken
    cost: dict[str, float] = dict.fromkeys(graph.nodes, 0.0)  # middleware seconds per second
    queues: dict[str, float] = dict.fromkeys(graph.nodes, 0.0)  # bytes held in endpoint queues
    for t in graph.topics.values():
        per_msg_s = (model.per_message_us + t.msg_bytes / 1024 * model.per_kib_us) / 1e6
        total_rate = sum(t.rate(p) for p in t.publishers)
        for p in t.publishers:
            msgs[p] += t.rate(p)
            cost[p] += t.rate(p) * per_msg_s
        for s in t.subscribers:
            taken = total_rate - t.rate(s)  # a node does not take its own messages
            msgs[s] += taken
            cost[s] += taken * per_msg_s
        for member in {*t.publishers, *t.subscribers}:
            queues[member] += model.history_depth * t.msg_bytes
    out = {}
    for name, node in graph.nodes.items():
        middleware = model.base_cores + cost[name]
        queue_mib = queues[name] / MIB
        profiled = node.memory_mib > 0
        out[name] = NodeProfile(
            cpu=node.cpu + middleware,
            memory_mib=node.memory_mib if profiled else model.process_mib + queue_mib,
            work_cores=node.cpu,
            middleware_cores=middleware,
            messages_per_s=msgs[name],
            memory_profiled=profiled,
            queue_mib=queue_mib,
        )
    return out
