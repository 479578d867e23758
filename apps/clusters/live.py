"""Live state of a cluster's pods: follow its pods and their Events, and let the apps that own pods store
each pod's phase, node and newest event on their rows; follow its Nodes too and keep each ComputeNode's
Ready status (the clusters app's own rows).

The clusters app runs the watcher (``python manage.py watch_cluster``), but the rows belong to apps above
it (a schedule's assignments, a placement's containers, RT-Kube's pods): each of them registers a handler in
its ``AppConfig.ready()`` with :func:`register_pod_handler`. A handler recognises its pods (by the labels its
push sets, or by its stored rows) and stores the state with :func:`store`, which writes only the rows whose
state changed (one UPDATE, none when nothing did): replaying a watch (a relist after 410 Gone, a restart)
leaves the database as it was.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

from django.db.models import Q, QuerySet
from django.utils import timezone

from apps.kube import gateway
from apps.kube.gateway import PodEvent, PodState
from apps.kube.informer import Informer

from . import metrics
from .kube import api_client_for
from .models import Cluster
from .nodes import NodeChange, NodeHandler, reconcile_nodes, record_node_status, status_of

log = logging.getLogger(__name__)

#: ``handler(cluster, state)`` -> rows it updated (0 when the pod is not its own or nothing changed).
PodHandler = Callable[[Cluster, PodState], int]

_HANDLERS: dict[str, PodHandler] = {}
#: Handlers that may see pods outside the cluster's own namespace (they join by the API's uid, not by labels).
_ANY_NAMESPACE: set[str] = set()


def register_pod_handler(name: str, handler: PodHandler, *, any_namespace: bool = False) -> None:
    """Register (or replace, by name) how an app stores the live state of its pods.

    A handler sees only the pods of the cluster's own namespace (``Cluster.namespace``, the one Continuum
    pushes to and owns, one fleet's per API: issue 25): labels are anyone's to write, so a pod elsewhere
    carrying a schedule's labels must not become that schedule's state. ``any_namespace``: the handler joins
    pods by namespace and uid to rows mirrored from the API itself (RT-Kube's pods), so it sees them all."""
    _HANDLERS[name] = handler
    if any_namespace:
        _ANY_NAMESPACE.add(name)
    else:
        _ANY_NAMESPACE.discard(name)


def pod_handlers() -> dict[str, PodHandler]:
    return dict(_HANDLERS)


def store(rows: QuerySet, values: dict[str, Any], at_field: str = "pod_state_at") -> int:
    """Set ``values`` on the ``rows`` that differ in any of them (and ``at_field`` to now); returns how many."""
    same = Q()
    for key, value in values.items():
        same &= Q(**{key: value})
    return rows.exclude(same).update(**values, **{at_field: timezone.now()})


def event_text(state: PodState, limit: int = 500) -> str:
    return state.event.text(limit) if state.event else ""


def live_values(state: PodState, **values: Any) -> dict[str, Any]:
    """``values`` plus ``pod_event`` when the pod's newest event is known: a pod seen before its Events (a
    restarted watcher gets the pods and the Events from two watches, in any order) keeps the stored one."""
    if state.event is not None:
        values["pod_event"] = event_text(state)
    return values


@dataclass
class LiveState:
    """The dispatcher: pods and their newest events in memory, each change handed to the handlers.

    ``on_pod`` and ``on_event`` take the watch events as they come (``{"type", "raw_object"}``, the server's
    JSON). A pod's state is dispatched when its signature (phase, node, deletion, newest event) changed."""

    cluster: Cluster
    handlers: dict[str, PodHandler] = field(default_factory=pod_handlers)
    pods: dict[tuple[str, str], PodState] = field(default_factory=dict)
    #: Newest events of pods not seen yet (an Event can come before its pod's watch reports it).
    pending: dict[tuple[str, str], tuple[str, PodEvent]] = field(default_factory=dict)
    sent: dict[tuple[str, str], tuple] = field(default_factory=dict)
    node_handlers: dict[str, NodeHandler] = field(default_factory=dict)
    node_changes: list[NodeChange] = field(default_factory=list)
    #: The cluster's Node objects as the watch last saw them (handlers may read them).
    nodes: Informer = field(default_factory=Informer)
    foreign: int = 0
    pod_events: int = 0
    node_events: int = 0
    nodes_updated: int = 0
    events: int = 0
    dispatched: int = 0
    updated: dict[str, int] = field(default_factory=dict)

    def on_pod(self, event: dict) -> int:
        obj = event.get("raw_object") or event.get("object") or {}
        kind = event.get("type")
        if kind not in ("ADDED", "MODIFIED", "DELETED") or not isinstance(obj, dict):
            return 0
        self.pod_events += 1
        state = gateway.pod_state(obj, deleted=kind == "DELETED")
        old = self.pods.get(state.key)
        latest = old.event if old is not None and old.uid == state.uid else None
        waiting = self.pending.pop(state.key, None)
        if waiting is not None and waiting[0] in ("", state.uid) and waiting[1].newer_than(latest):
            latest = waiting[1]
        state = state.with_event(latest)
        if state.deleted:
            self.pods.pop(state.key, None)
        else:
            self.pods[state.key] = state
        return self.dispatch(state)

    def on_event(self, event: dict) -> int:
        obj = event.get("raw_object") or event.get("object") or {}
        if event.get("type") not in ("ADDED", "MODIFIED") or not isinstance(obj, dict):
            return 0
        about = gateway.event_of(obj)
        if about is None:
            return 0
        self.events += 1
        key, uid, pod_event = about
        state = self.pods.get(key)
        if state is None or (uid and state.uid and uid != state.uid):
            held = self.pending.get(key)
            if held is None or pod_event.newer_than(held[1]):
                self.pending[key] = (uid, pod_event)
            return 0
        if not pod_event.newer_than(state.event):
            return 0
        state = state.with_event(pod_event)
        self.pods[key] = state
        return self.dispatch(state)

    def on_node(self, event: dict) -> int:
        """A Node's Ready status onto its ComputeNode row (a deleted node is NotReady); rows of nodes Continuum
        does not know are not created (``kube_sync`` adds them)."""
        obj = event.get("raw_object") or event.get("object") or {}
        if event.get("type") not in ("ADDED", "MODIFIED", "DELETED") or not isinstance(obj, dict):
            return 0
        self.node_events += 1
        self.nodes.apply(event)
        status = status_of(None if event["type"] == "DELETED" else obj)
        change = record_node_status(self.cluster, gateway.name_of(obj), status)
        if change is None:
            return 0
        self.nodes_updated += 1
        self.node_changes.append(change)
        self.on_nodes([change], listed=False)
        return 1

    def on_node_list(self, items: list[dict]) -> int:
        """A full list of the nodes (at start, after a lost watch): every row reconciled, the handlers told."""
        self.nodes.replace(items)
        changes = reconcile_nodes(self.cluster, items)
        self.nodes_updated += len(changes)
        self.node_changes.extend(changes)
        self.on_nodes(changes, listed=True)
        return len(changes)

    def on_nodes(self, changes: list[NodeChange], listed: bool) -> None:
        for name, handler in self.node_handlers.items():
            try:
                handler(self.cluster, changes, listed)
            except Exception:  # one app's bug must not stop the others
                log.exception("node handler %s failed on cluster %s", name, getattr(self.cluster, "pk", None))
                metrics.handler_failed(name)

    def dispatch(self, state: PodState) -> int:
        signature = state.signature()
        if self.sent.get(state.key) == signature:
            return 0
        if state.deleted:
            self.sent.pop(state.key, None)
        else:
            self.sent[state.key] = signature
        self.dispatched += 1
        total = 0
        own = self.cluster is None or state.namespace == self.cluster.namespace
        if not own:
            self.foreign += 1
        for name, handler in self.handlers.items():
            if not own and name not in _ANY_NAMESPACE:
                continue  # not Continuum's namespace: its labels prove nothing (see register_pod_handler)
            try:
                count = handler(self.cluster, state)
            except Exception:  # one app's bug must not stop the others' live state
                log.exception("pod handler %s failed on %s/%s", name, state.namespace, state.name)
                metrics.handler_failed(name)
                continue
            if count:
                self.updated[name] = self.updated.get(name, 0) + count
                total += count
        return total

    def report(self) -> dict:
        return {
            "cluster": getattr(self.cluster, "pk", None),
            "pod_events": self.pod_events,
            "node_events": self.node_events,
            "nodes_updated": self.nodes_updated,
            "events": self.events,
            "pods": len(self.pods),
            "dispatched": self.dispatched,
            "updated": dict(sorted(self.updated.items())),
        }


def watch_cluster(
    cluster: Cluster,
    namespaces: Iterable[str] | None = None,
    *,
    timeout: float | None = None,
    stop: threading.Event | None = None,
    retries: int | None = 5,
    handlers: dict[str, PodHandler] | None = None,
    on_change: Callable[[LiveState], Any] | None = None,
    node_handlers: dict[str, NodeHandler] | None = None,
) -> dict:
    """Follow the Nodes, and the pods and pod Events of ``cluster`` (in ``namespaces``; default: all), until
    ``stop`` is set or ``timeout`` seconds passed, dispatching each change to the handlers; returns counts.

    The two watches (per namespace) run in threads that only queue what they receive; this thread, the
    caller's, does every database write (so a test's transaction sees them)."""
    live = LiveState(
        cluster,
        handlers if handlers is not None else pod_handlers(),
        node_handlers=node_handlers if node_handlers is not None else {},
    )
    stop = stop or threading.Event()
    halt = threading.Event()  # ends the watch threads: set when ``stop`` is, at the deadline, or on a failure
    inbox: queue.Queue = queue.Queue()
    watches = gateway.Watches()
    stats: list[gateway.WatchStats] = []
    scopes = sorted(set(namespaces)) if namespaces else [None]
    deadline = None if timeout is None else time.monotonic() + timeout

    def run(kind: str, pick, what: str) -> None:
        mine = gateway.WatchStats()
        stats.append(mine)
        try:
            gateway.follow(
                lambda: api_client_for(cluster),
                pick,
                lambda event: inbox.put((kind, event)),
                # Nodes are listed first: rows of nodes gone while nobody watched become NotReady (level-triggered).
                on_list=(lambda items: inbox.put(("nodes", items))) if kind == "node" else None,
                stop=halt,
                retries=retries,
                what=what,
                watches=watches,
                stats=mine,
            )
        except BaseException as exc:  # handed to the dispatching thread, which raises it
            inbox.put(("error", exc))

    threads = [
        threading.Thread(
            target=run, args=("node", gateway.watch_nodes(), f"node watch of cluster {cluster.name!r}"), daemon=True
        )
    ]
    for ns in scopes:
        where = f"namespace {ns}" if ns else "all namespaces"
        for kind, pick in (
            ("pod", gateway.watch_pods(ns)),
            ("event", gateway.watch_events(ns, field_selector="involvedObject.kind=Pod")),
        ):
            thread = threading.Thread(
                target=run, args=(kind, pick, f"{kind} watch of cluster {cluster.name!r} ({where})"), daemon=True
            )
            threads.append(thread)
    for thread in threads:
        thread.start()

    def handle(kind: str, payload: Any) -> None:
        if kind == "error":
            raise payload
        metrics.event(cluster.pk, kind)
        changed = {"pod": live.on_pod, "event": live.on_event, "node": live.on_node, "nodes": live.on_node_list}[kind](
            payload
        )
        if changed and on_change is not None:
            on_change(live)

    try:
        while not stop.is_set():
            left = None if deadline is None else deadline - time.monotonic()
            if left is not None and left <= 0:
                break
            try:
                kind, payload = inbox.get(timeout=min(0.5, left) if left is not None else 0.5)
            except queue.Empty:
                continue
            handle(kind, payload)
        while True:  # what already arrived is stored too
            try:
                kind, payload = inbox.get_nowait()
            except queue.Empty:
                break
            if kind != "error":
                handle(kind, payload)
    finally:
        halt.set()
        watches.close_all()
        for thread in threads:
            thread.join(timeout=15)
    report = live.report()
    report.update(
        namespaces=[ns for ns in scopes if ns] or ["*"],
        lists=sum(s.lists for s in stats),
        node_changes=[c.to_dict() for c in live.node_changes],
        foreign_pods=live.foreign,
        reconnects=sum(s.reconnects for s in stats),
    )
    return report
