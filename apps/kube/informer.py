"""An informer cache: the view of the API between lists (thesis 3.4, Fig. 3.34). The RT scheduler keeps its
pods and nodes in it, the cluster agent its nodes (``apps.clusters.live.LiveState.nodes``).

kube-scheduler does not list the cluster for each pod it places: its informers list once, then follow the
watch, and each scheduling cycle reads the cache. :class:`Informer` is that cache for one collection: filled
by the watch thread (``replace`` with the list, ``apply`` with each event), read by the scheduler's cycle
(``snapshot``), and marked stale while the watch is reconnecting (the cycle then lists from the API, as it
does without a watch).

Pods bound by this process are *assumed* bound (kube-scheduler's assume cache): the cycle after a Binding may
run before the watch reports the pod's ``nodeName``, and a stale event may report the pod unbound again (a
watch replayed from an older resourceVersion). A pod's ``nodeName`` never changes once set, so the assumption
holds for as long as the pod (same uid) exists: the snapshot shows the pod bound to the node this process
bound it to, and it is never bound twice. Assumptions end when the pod is deleted (or absent from a new list).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable
from typing import Any

Key = Callable[[dict], str]


def object_key(obj: dict) -> str:
    meta = obj.get("metadata") or {}
    namespace = meta.get("namespace")
    return f"{namespace}/{meta.get('name')}" if namespace else str(meta.get("name"))


def _uid(obj: dict | None) -> str | None:
    return ((obj or {}).get("metadata") or {}).get("uid")


class Informer:
    """Objects of one collection by ``namespace/name`` (see the module docstring); thread-safe.

    ``relevant(old, new)`` says whether a change matters to the scheduler (``new`` None: deleted): ``apply``
    returns it, and the watch thread wakes the scheduler only then (a hollow kubelet's status updates do not
    need a scheduling cycle)."""

    def __init__(self, relevant: Callable[[dict | None, dict | None], bool] | None = None) -> None:
        self._lock = threading.Lock()
        self._objects: dict[str, dict] = {}
        self._assumed: dict[str, tuple[str, str]] = {}  # key -> (uid, node) bound by this process
        self._relevant = relevant or (lambda old, new: True)
        self.synced = False
        self.lists = 0
        self.events = 0
        self.stale_events = 0

    def unsynced(self) -> None:
        """The watch is (re)connecting: events may have been missed until the next list."""
        with self._lock:
            self.synced = False

    def replace(self, items: Iterable[dict]) -> bool:
        """A fresh list: the cache becomes exactly it. True (always relevant: anything may have changed)."""
        objects = {object_key(o): o for o in items}
        with self._lock:
            self._objects = objects
            self._assumed = {k: a for k, a in self._assumed.items() if _uid(objects.get(k)) == a[0]}
            self.synced = True
            self.lists += 1
        return True

    def apply(self, event: dict) -> bool:
        """One watch event (``type``, ``raw_object``); whether it is relevant (see the class docstring)."""
        kind, obj = event.get("type"), event.get("raw_object")
        if kind not in ("ADDED", "MODIFIED", "DELETED") or not isinstance(obj, dict):
            return False  # BOOKMARK, ERROR (the watch loop handles 410 Gone)
        key = object_key(obj)
        with self._lock:
            self.events += 1
            old = self._objects.get(key)
            if kind == "DELETED":
                self._objects.pop(key, None)
                self._assumed.pop(key, None)
                return self._relevant(old, None)
            uid = (obj.get("metadata") or {}).get("uid")
            assumed = self._assumed.get(key)
            if assumed is not None and assumed[0] != uid:
                del self._assumed[key]  # a new pod of the same name: not the one this process bound
            elif assumed is not None and not (obj.get("spec") or {}).get("nodeName"):
                self.stale_events += 1  # reported unbound after this process bound it: an older state
            self._objects[key] = obj
            return self._relevant(old, obj)

    def assume(self, key: str, uid: str, node: str) -> None:
        """This process bound pod ``key`` (of ``uid``) to ``node``: the snapshot shows it bound there."""
        with self._lock:
            self._assumed[key] = (uid, node)

    def forget(self, key: str, uid: str) -> None:
        """The Binding of pod ``key`` (of ``uid``) failed: it is pending again (unless the watch says otherwise)."""
        with self._lock:
            if self._assumed.get(key, ("",))[0] == uid:
                del self._assumed[key]

    def assumed(self, key: str) -> str | None:
        with self._lock:
            a = self._assumed.get(key)
        return a[1] if a else None

    def snapshot(self) -> list[dict]:
        """The cached objects; a pod this process bound and the cache still shows unbound, bound (a copy)."""
        with self._lock:
            objects = dict(self._objects)
            assumed = dict(self._assumed)
        for key, (uid, node) in assumed.items():
            obj = objects.get(key)
            if obj is None or (obj.get("metadata") or {}).get("uid") != uid:
                continue
            spec = obj.get("spec") or {}
            if not spec.get("nodeName"):
                objects[key] = {**obj, "spec": {**spec, "nodeName": node}}
        return list(objects.values())

    def __len__(self) -> int:
        with self._lock:
            return len(self._objects)

    def stats(self) -> dict[str, Any]:
        with self._lock:
            return {"objects": len(self._objects), "assumed": len(self._assumed), "lists": self.lists,
                    "events": self.events, "stale_events": self.stale_events, "synced": self.synced}  # fmt: skip
