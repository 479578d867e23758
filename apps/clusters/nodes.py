"""A node's status, written by one function with one rule (issue 28), and the node handlers of the cluster agent.

The rule (:func:`status_of`): the API's Ready condition (``True`` Ready, ``False`` NotReady, anything else or
none: Unknown, what the node lifecycle controller sets when a kubelet stops posting); a node gone from the API
is NotReady. Ready is the only status that counts as ready: NotReady and Unknown both do not
(:data:`NOT_READY_Q`), and a node that leaves Ready raises the alarm (a warning in the log, the home page's
"not ready" count in red, ``continuum_nodes_not_ready`` on ``/metrics``).

Every writer of a node's status (the cluster agent, ``kube_sync``, HEFT4K's node watcher) goes through
:func:`record_node_status`; apps that act on node changes register a :data:`NodeHandler` with
:func:`register_node_handler` in their ``AppConfig.ready()`` (HEFT4K's remap trigger) instead of watching nodes.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from django.db.models import Q

from apps.kube import gateway

from .models import Cluster, ComputeNode

log = logging.getLogger("continuum.nodes")

READY = ComputeNode.Status.READY
#: Nodes that do not count as ready: NotReady and Unknown alike.
NOT_READY_Q = ~Q(status=READY)


@dataclass(frozen=True)
class NodeChange:
    node: str
    was: str
    status: str

    @property
    def went_down(self) -> bool:
        return self.was == READY and self.status != READY

    def to_dict(self) -> dict[str, str]:
        return {"node": self.node, "status": self.status, "was": self.was}


#: ``handler(cluster, changes, listed)``: called after node statuses changed (``changes``) or after a full list
#: (``listed`` True: level-triggered handlers re-check everything then).
NodeHandler = Callable[[Cluster, list[NodeChange], bool], Any]
_NODE_HANDLERS: dict[str, NodeHandler] = {}


def register_node_handler(name: str, handler: NodeHandler) -> None:
    """Register (or replace, by name) what an app does when a cluster's nodes change."""
    _NODE_HANDLERS[name] = handler


def node_handlers() -> dict[str, NodeHandler]:
    return dict(_NODE_HANDLERS)


def status_of(obj: Mapping[str, Any] | None) -> str:
    """The rule: the Ready condition's status, NotReady for a node gone from the API (``None``)."""
    return ComputeNode.Status.NOT_READY if obj is None else gateway.node_status(obj)


def record_node_status(cluster: Cluster, name: str, status: str) -> NodeChange | None:
    """Store a node's status on its row; the change, or None (unknown node: ``kube_sync`` adds it; unchanged)."""
    row = ComputeNode.objects.filter(cluster=cluster, name=name).only("pk", "status").first()
    if row is None or row.status == status:
        return None
    change = NodeChange(name, row.status, status)
    ComputeNode.objects.filter(pk=row.pk).update(status=status)
    if change.went_down:
        log.warning("ALARM: node %s of cluster %s (%s) is %s (was %s)", name, cluster.name, cluster.pk, status,
                    change.was)  # fmt: skip
    else:
        log.info("node %s of cluster %s: %s -> %s", name, cluster.name, change.was, status)
    return change


def reconcile_nodes(cluster: Cluster, items: list[Mapping[str, Any]]) -> list[NodeChange]:
    """A full list of the API's nodes onto the rows (level-triggered): a row missing from the list is NotReady."""
    statuses = {gateway.name_of(n): status_of(n) for n in items}
    changes = []
    for name in cluster.nodes.values_list("name", flat=True):
        change = record_node_status(cluster, name, statuses.get(name, status_of(None)))
        if change is not None:
            changes.append(change)
    return changes
