"""The one watch loop: follow a collection (list, then watch from its resourceVersion), resume after the
server ends a watch, start over when the resourceVersion expired (410 Gone), and back off exponentially
after failures.

Used by HEFT4K's node watcher (list first, reconcile, then follow the changes) and by RT-Kube's scheduler
(pods, RealTime and Monitoring objects; no list: the first watch's synthetic ADDED events are the list).
"""

from __future__ import annotations

import json
import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from kubernetes import client, watch
from kubernetes.client.exceptions import ApiException

from .connect import API_ERRORS, REQUEST_TIMEOUT, KubeError, describe, read_json

log = logging.getLogger(__name__)
#: Longest single watch request (seconds); the server ends it and the loop re-opens it.
WATCH_SECONDS = 60
GONE = 410
MAX_BACKOFF = 30.0

#: ``pick(api_client)`` -> the generated list method to follow and its positional and keyword arguments.
Pick = Callable[[client.ApiClient], tuple[Callable, tuple, dict]]


@dataclass
class WatchStats:
    """What one run of :func:`follow` saw: events, lists and reconnects after failures."""

    events: int = 0
    lists: int = 0
    reconnects: int = 0


class Watches:
    """The open watch streams of a process, so that stopping can interrupt reads blocked on the server."""

    def __init__(self) -> None:
        self._open: set[watch.Watch] = set()
        self._lock = threading.Lock()

    def add(self, w: watch.Watch) -> None:
        with self._lock:
            self._open.add(w)

    def discard(self, w: watch.Watch) -> None:
        with self._lock:
            self._open.discard(w)

    def close_all(self) -> None:
        """Interrupt every open watch connection (a blocked read would otherwise wait for the server's timeout)."""
        with self._lock:
            watches = list(self._open)
        for w in watches:
            w.stop()
            resp = getattr(w, "_resp", None)
            if resp is not None:
                try:
                    resp.shutdown() if hasattr(resp, "shutdown") else resp.close()
                except Exception as exc:  # best effort while stopping
                    log.debug("closing a watch: %s", exc)


class JsonWatch(watch.Watch):
    """The client's watch with events as the server's JSON, decoded once. (``Watch(return_type="object")`` decodes
    each line, encodes the object again and decodes that copy: three passes over every pod for a result
    identical to the first; a pod watch's thread spent most of its CPU there.)"""

    def __init__(self) -> None:
        super().__init__(return_type="object")

    def unmarshal_event(self, data, return_type):
        if not data or data.isspace():
            return None
        try:
            js = json.loads(data)
        except json.JSONDecodeError:
            return None
        obj = js.get("object")
        js["raw_object"] = obj
        if js.get("type") not in ("ERROR", None) and isinstance(obj, dict):
            version = (obj.get("metadata") or {}).get("resourceVersion")
            if version:
                self.resource_version = version
        return js


def _version_of(obj: Any) -> str | None:
    if isinstance(obj, dict):
        return (obj.get("metadata") or {}).get("resourceVersion")
    metadata = getattr(obj, "metadata", None)
    return getattr(metadata, "resource_version", None)


def follow(
    connect: Callable[[], client.ApiClient],
    pick: Pick,
    on_event: Callable[[dict], None],
    *,
    on_list: Callable[[list[dict]], None] | None = None,
    stop: threading.Event | None = None,
    timeout: float | None = None,
    retries: int | None = 5,
    backoff: float = 1.0,
    max_backoff: float = MAX_BACKOFF,
    sleep: Callable[[float], Any] | None = None,
    watch_seconds: int = WATCH_SECONDS,
    what: str = "watch",
    watches: Watches | None = None,
    retry_on: tuple[type[BaseException], ...] = API_ERRORS,
    stats: WatchStats | None = None,
) -> WatchStats:
    """Follow a collection until ``stop`` is set or ``timeout`` seconds passed (forever when both are None).

    - ``connect()`` builds the API client (again after each failure, so a changed kubeconfig is picked up);
      ``pick(api_client)`` names the list method to follow, e.g. ``(core.list_node, (), {})``.
    - With ``on_list``, the collection is listed first (``on_list(items)``, the server's JSON) and watched
      from the list's resourceVersion; without, the first watch starts from "now" with the current objects
      as ADDED events. Either way, a watch the server ended is resumed from the last resourceVersion seen,
      and an expired one (410 Gone) starts over (list again, or a fresh watch).
    - ``on_event(event)``: ``{"type", "object", "raw_object"}``, both objects the server's JSON (dicts).
    - A failure in ``retry_on`` (by default: the API unreachable or refusing) is retried after
      ``min(backoff * 2**(n-1), max_backoff)`` seconds (``n`` failures in a row); after ``retries`` in a row
      (``None``: never) :class:`KubeError` says why (``"{what} gave up after {retries} reconnects: ..."``).
    """
    stats = stats if stats is not None else WatchStats()
    deadline = None if timeout is None else time.monotonic() + timeout
    wait = sleep or (stop.wait if stop is not None else time.sleep)

    def left() -> float:
        return float("inf") if deadline is None else deadline - time.monotonic()

    def stopped() -> bool:
        return (stop is not None and stop.is_set()) or left() <= 0

    failures = 0
    version: str | None = None
    while not stopped():
        server = ""
        try:
            with connect() as api_client:
                server = api_client.configuration.host
                fn, args, kwargs = pick(api_client)
                while not stopped():
                    if version is None and on_list is not None:
                        listing = read_json(fn, *args, **kwargs) or {}
                        version = (listing.get("metadata") or {}).get("resourceVersion")
                        stats.lists += 1
                        on_list(listing.get("items") or [])
                        failures = 0
                    seconds = max(1, int(min(left(), watch_seconds)))
                    w = JsonWatch()  # events as the server's JSON: no model to outgrow
                    if watches is not None:
                        watches.add(w)
                    options = dict(kwargs, timeout_seconds=seconds, _request_timeout=(REQUEST_TIMEOUT[0], seconds + 10))
                    if version is not None:
                        options["resource_version"] = version
                    try:
                        for event in w.stream(fn, *args, **options):
                            if stop is not None and stop.is_set():
                                w.stop()
                                break
                            failures = 0
                            stats.events += 1
                            version = _version_of(event.get("raw_object")) or version
                            on_event(event)
                            if stopped():
                                w.stop()
                                break
                        else:
                            failures = 0  # the server ended the watch as asked: resume from ``version``
                    finally:
                        if watches is not None:
                            watches.discard(w)
        except ApiException as exc:
            if exc.status == GONE:  # the resourceVersion is too old: list (or watch) afresh
                version = None
                continue
            if not isinstance(exc, retry_on):
                raise
            failures = _failed(exc, failures, retries, backoff, max_backoff, left(), server, what, wait, stats)
            version = None
        except retry_on as exc:
            if stopped():
                break
            failures = _failed(exc, failures, retries, backoff, max_backoff, left(), server, what, wait, stats)
            version = None  # events may have been missed: start over
    return stats


def _failed(exc, failures, retries, backoff, max_backoff, left, server, what, wait, stats) -> int:
    """Count a failure; give up after ``retries`` in a row, else wait (exponential backoff)."""
    failures += 1
    reason = describe(exc, server) if isinstance(exc, API_ERRORS) else str(exc)
    if retries is not None and failures > retries:
        raise KubeError(f"{what} gave up after {retries} reconnects: {reason}") from exc
    stats.reconnects += 1
    delay = min(backoff * 2 ** (failures - 1), max_backoff, max(0.0, left))
    log.warning("%s: %s; reconnecting in %.1f s", what, reason, delay)
    if delay > 0:
        wait(delay)
    return failures


# -- what to follow ---------------------------------------------------------------------------------------------


def nodes() -> Pick:
    """The cluster's Node objects."""
    return lambda api_client: (client.CoreV1Api(api_client).list_node, (), {})


def pods(namespace: str | None, **query) -> Pick:
    """Pods of one namespace (``None``: of all), e.g. with a ``field_selector``."""

    def pick(api_client: client.ApiClient):
        core = client.CoreV1Api(api_client)
        if namespace is None:
            return core.list_pod_for_all_namespaces, (), dict(query)
        return core.list_namespaced_pod, (namespace,), dict(query)

    return pick


def events(namespace: str | None, **query) -> Pick:
    """core/v1 Events of one namespace (``None``: of all), e.g. ``field_selector="involvedObject.kind=Pod"``."""

    def pick(api_client: client.ApiClient):
        core = client.CoreV1Api(api_client)
        if namespace is None:
            return core.list_event_for_all_namespaces, (), dict(query)
        return core.list_namespaced_event, (namespace,), dict(query)

    return pick


def custom_objects(group: str, version: str, plural: str, namespace: str | None) -> Pick:
    """Custom objects of one kind, in one namespace (``None``: in all)."""

    def pick(api_client: client.ApiClient):
        api = client.CustomObjectsApi(api_client)
        if namespace is None:
            return api.list_cluster_custom_object, (group, version, plural), {}
        return api.list_namespaced_custom_object, (group, version, namespace, plural), {}

    return pick
