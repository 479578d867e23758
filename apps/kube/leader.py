"""Leader election with a ``coordination.k8s.io/v1`` Lease: client-go's protocol (``tools/leaderelection``).

Replicas of one component (the RT scheduler, the cluster agent) share one Lease; the holder works, the others
wait. The record is client-go's, in the Lease's spec: ``holderIdentity``, ``leaseDurationSeconds``,
``acquireTime``, ``renewTime``, ``leaseTransitions``. The rules, as ``tryAcquireOrRenew`` has them:

- A candidate takes the Lease when it does not exist (create), when its holder is empty (released), or when
  the record has not changed for ``lease_duration`` seconds *of the candidate's own clock*: the time is when
  this process last saw the record change (``observedTime``), never the holder's ``renewTime``, so clocks
  need not agree. Taking it sets ``acquireTime`` and adds one to ``leaseTransitions``.
- The holder renews ``renewTime`` every ``retry_period``; every write is an update at the resourceVersion read
  (optimistic concurrency: of two candidates writing at once, one gets 409 Conflict and stays a follower).
- A holder that could not renew for ``renew_deadline`` (< ``lease_duration``) stops leading *before* anyone
  else may take the Lease: its work is cancelled (the ``lost`` event) and it becomes a candidate again.
- Stopping cleanly releases the Lease (empty holder): a successor takes it at its next try, not after the
  lease duration (client-go's ``ReleaseOnCancel``).

So after ``kill -9`` of the holder a follower leads within ``lease_duration + retry_period`` of the holder's
last renewal. Two leaders at once would need a paused holder that resumes past its renew deadline; what the
followers do is still safe in that window (a pod's Binding is refused with 409 once the pod is bound).
"""

from __future__ import annotations

import logging
import os
import socket
import threading
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any

from kubernetes import client
from kubernetes.client.exceptions import ApiException
from prometheus_client import Gauge

from continuum.metrics import PREFIX

from .connect import API_ERRORS, read_json

log = logging.getLogger("continuum.leader")
#: client-go's ``leader_election_master_status``: 1 while this process holds the Lease ``name``.
LEADING = Gauge(f"{PREFIX}_leader_election_master_status", "1 while this process leads, by Lease name", ["name"])
NOT_FOUND, CONFLICT = 404, 409


def identity() -> str:
    """``hostname_uuid``, as client-go's callers build it: unique per process, readable in the Lease."""
    return f"{os.environ.get('POD_NAME') or socket.gethostname()}_{uuid.uuid4()}"


def micro_time(t: datetime | None = None) -> str:
    """A ``MicroTime`` (RFC 3339 with microseconds, UTC)."""
    return (t or datetime.now(UTC)).strftime("%Y-%m-%dT%H:%M:%S.%fZ")


@dataclass(frozen=True)
class Timing:
    """client-go's defaults are 15 s, 10 s, 2 s; ``renew_deadline`` must be below ``lease_duration``."""

    lease_duration: float = 15.0
    renew_deadline: float = 10.0
    retry_period: float = 2.0

    def __post_init__(self) -> None:
        if not 0 < self.retry_period < self.renew_deadline < self.lease_duration:
            raise ValueError("leader election needs 0 < retry_period < renew_deadline < lease_duration")


class LeaseLock:
    """One Lease, read and written as the server's JSON (``namespace/name``) with ``connect()``'s client."""

    def __init__(self, connect: Callable[[], client.ApiClient], namespace: str, name: str, holder: str) -> None:
        self.connect = connect
        self.namespace, self.name, self.holder = namespace, name, holder

    def get(self, api: client.CoordinationV1Api) -> dict | None:
        try:
            return read_json(api.read_namespaced_lease, self.name, self.namespace)
        except ApiException as exc:
            if exc.status == NOT_FOUND:
                return None
            raise

    def create(self, api: client.CoordinationV1Api, spec: dict) -> dict:
        body = {"apiVersion": "coordination.k8s.io/v1", "kind": "Lease",
                "metadata": {"name": self.name, "namespace": self.namespace}, "spec": spec}  # fmt: skip
        return read_json(api.create_namespaced_lease, self.namespace, body)

    def update(self, api: client.CoordinationV1Api, current: dict, spec: dict) -> dict:
        body = {**current, "spec": spec}  # metadata.resourceVersion kept: a concurrent write answers 409
        return read_json(api.replace_namespaced_lease, self.name, self.namespace, body)


class LeaderElector:
    """client-go's elector for one Lease (see the module docstring). ``run(work, stop)`` campaigns until
    ``stop``; each time it leads it calls ``work(lost)`` in this thread, with ``lost`` set when leadership ends
    (renewal failed past the deadline, or ``stop``)."""

    def __init__(self, lock: LeaseLock, timing: Timing | None = None, on_change: Callable[[bool], Any] | None = None):
        self.lock = lock
        self.timing = timing or Timing()
        self.on_change = on_change
        self._observed: tuple[str, float] | None = None  # (record as last seen, monotonic time it was seen)
        self.leading = False
        self.transitions_seen = 0

    # -- one try, as client-go's tryAcquireOrRenew ---------------------------------------------------------
    def try_acquire_or_renew(self) -> bool:
        lock, now = self.lock, datetime.now(UTC)
        with lock.connect() as api_client:
            api = client.CoordinationV1Api(api_client)
            current = lock.get(api)
            mine = {"holderIdentity": lock.holder, "leaseDurationSeconds": max(1, round(self.timing.lease_duration)),
                    "acquireTime": micro_time(now), "renewTime": micro_time(now), "leaseTransitions": 0}  # fmt: skip
            if current is None:
                try:
                    written = lock.create(api, mine)
                except ApiException as exc:
                    if exc.status == CONFLICT:  # another candidate created it first
                        return False
                    raise
                self._observe(written)
                return True
            spec = current.get("spec") or {}
            self._observe(current)
            holder = spec.get("holderIdentity") or ""
            if holder and holder != lock.holder and not self._expired():
                return False  # held by another, and renewed within the lease duration (by our clock)
            if holder == lock.holder:
                mine["acquireTime"] = spec.get("acquireTime") or mine["acquireTime"]
                mine["leaseTransitions"] = spec.get("leaseTransitions") or 0
            else:
                mine["leaseTransitions"] = (spec.get("leaseTransitions") or 0) + 1
            try:
                written = lock.update(api, current, mine)
            except ApiException as exc:
                if exc.status == CONFLICT:  # someone wrote between our read and write: follow them
                    return False
                raise
            self._observe(written)
            return True

    def _observe(self, lease: dict) -> None:
        record = repr(sorted((lease.get("spec") or {}).items()))
        if self._observed is None or self._observed[0] != record:
            self._observed = (record, time.monotonic())

    def _expired(self) -> bool:
        assert self._observed is not None
        return time.monotonic() > self._observed[1] + self.timing.lease_duration

    def _try(self) -> bool:
        try:
            return self.try_acquire_or_renew()
        except API_ERRORS as exc:
            log.warning("lease %s/%s: %s", self.lock.namespace, self.lock.name, exc)
            return False

    # -- the loop ------------------------------------------------------------------------------------------
    def run(self, work: Callable[[threading.Event], Any], stop: threading.Event) -> None:
        while not stop.is_set():
            if not self._try():
                stop.wait(self.timing.retry_period)
                continue
            self._lead(work, stop)

    def _lead(self, work: Callable[[threading.Event], Any], stop: threading.Event) -> None:
        lost = threading.Event()
        self._set_leading(True)
        log.warning("lease %s/%s: %s leads", self.lock.namespace, self.lock.name, self.lock.holder)

        def renew() -> None:
            last = time.monotonic()
            while not lost.is_set():
                if stop.wait(self.timing.retry_period):
                    break
                if self._try():
                    last = time.monotonic()
                elif time.monotonic() - last > self.timing.renew_deadline:
                    log.warning("lease %s/%s: not renewed for %.1f s: stepping down", self.lock.namespace,
                                self.lock.name, time.monotonic() - last)  # fmt: skip
                    break
            lost.set()

        renewer = threading.Thread(target=renew, daemon=True, name=f"lease-{self.lock.name}")
        renewer.start()
        try:
            work(lost)
        finally:
            lost.set()
            renewer.join(timeout=self.timing.retry_period * 2 + 10)
            self._set_leading(False)
            if stop.is_set():
                self.release()

    def _set_leading(self, leading: bool) -> None:
        self.leading = leading
        LEADING.labels(self.lock.name).set(1 if leading else 0)
        if self.on_change is not None:
            self.on_change(leading)

    def release(self) -> None:
        """Give the Lease up (empty holder), so a successor need not wait for it to expire."""
        try:
            with self.lock.connect() as api_client:
                api = client.CoordinationV1Api(api_client)
                current = self.lock.get(api)
                spec = (current or {}).get("spec") or {}
                if current is None or spec.get("holderIdentity") != self.lock.holder:
                    return
                now = micro_time()
                released = {**spec, "holderIdentity": "", "leaseDurationSeconds": 1, "renewTime": now,
                            "acquireTime": now}  # fmt: skip
                self.lock.update(api, current, released)
        except (ApiException, *API_ERRORS) as exc:
            log.warning("lease %s/%s: release failed: %s", self.lock.namespace, self.lock.name, exc)
