"""The RT scheduler's writer of rows (see :mod:`apps.realtime.scheduler`): each cycle's pods in the ledger
(:class:`~apps.realtime.models.RTPod`) and its new decisions (:class:`~apps.realtime.models.RTDecision`).

While the scheduler loops, a writer thread writes them after the binds, from a bounded queue drained in
batches at most every ``WRITE_EVERY`` seconds (one ledger upsert and one commit for several cycles): the path
from a pod's watch event to its Binding holds no database write. A cycle run on its own writes them inline.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from datetime import datetime
from typing import TYPE_CHECKING, NamedTuple

from django.db import close_old_connections, connection, transaction
from django.utils import timezone

from apps.clusters.models import Cluster
from continuum.engine.rtkube import rt_kube
from continuum.engine.rtkube.rt_model import NONE

from . import sync
from .kube import parse_time
from .models import RTDecision, RTPlan, RTPod

if TYPE_CHECKING:
    from .scheduler import PodView

log = logging.getLogger("continuum.rt_scheduler")

#: Bounded: a database slower than the binds makes the loop wait (back-pressure), never grow without end.
WRITE_QUEUE = 64
#: The writer writes at most this often (seconds): while pods stream in, a cycle every ~25 ms each upserted the
#: ledger of every pod (and looked for gone ones) in the writer's own batch, beside the Bindings for the GIL and
#: the database's CPU; the rows and decisions of several cycles now go together, at most this late.
WRITE_EVERY = 0.25


class LedgerRow(NamedTuple):
    """The RTPod fields a cycle writes from the API's view of a pod (besides deleted_at, cleared and seen), named
    after the model's attnames: one definition for the row built, the comparison with the last one written and
    the upsert's update_fields."""

    uid: str
    node: str
    container_name: str
    scheduler_name: str
    realtime_id: int | None
    criticality: str
    stateless: bool
    cpu: float
    memory_mib: float
    utilization: float | None
    owned: bool
    phase: str
    bound_at: datetime | None


class CycleWrite(NamedTuple):
    """One cycle's rows: its pods' views, the pods it bound ((namespace, name) -> (node, utilisation)), its plan
    and its new decisions ((view, decision, outcome, message) each)."""

    cluster: Cluster
    views: list[PodView]
    bound: dict[tuple[str, str], tuple[str, float]]
    plan: object
    fresh: list


class LedgerWriter:
    """Writes the ledger rows and decisions of one cluster's RT scheduler (``namespace`` as the scheduler's)."""

    def __init__(self, namespace: str | None) -> None:
        self.namespace = namespace
        #: Cycles written, and batches that failed (logged; the next batch writes every row that differs again).
        self.writes = 0
        self.write_errors = 0
        #: Monotonic time of the last cycle handed over (written or queued).
        self.last_cycle = 0.0
        self._queue: queue.Queue[CycleWrite | None] | None = None
        self._thread: threading.Thread | None = None
        self._closing = threading.Event()
        self._rewrite = threading.Event()
        #: (namespace, name) -> the ledger row as this process last wrote it: a row unchanged since is not
        #: written again (a cycle of 1,000 pods would upsert them all) and a pod gone since is marked deleted
        #: without reading the live rows back, except after rewrite_all (each sync), when every row is written
        #: and the live rows are read (what another writer changed meanwhile is reconciled then).
        self._recorded: dict[tuple[str, str], LedgerRow] = {}

    @property
    def threaded(self) -> bool:
        return self._queue is not None

    def start(self) -> None:
        """Write from a thread from now on (until :meth:`stop`)."""
        self._closing.clear()
        self._queue = queue.Queue(maxsize=WRITE_QUEUE)
        self._thread = threading.Thread(target=self._loop, args=(self._queue,), daemon=True, name="rt-writer")
        self._thread.start()

    def stop(self, timeout: float = 60) -> None:
        """Write what is queued, then end the thread; inline writes from then on."""
        if self._queue is None or self._thread is None:
            return
        self._closing.set()  # the batch of WRITE_EVERY seconds is not waited for
        self._queue.put(None)
        self._thread.join(timeout=timeout)
        self._queue = self._thread = None

    def rewrite_all(self) -> None:
        """Every ledger row is written, and the live rows read back, at the next write (after a sync)."""
        self._rewrite.set()

    def write(self, cycle: CycleWrite) -> None:
        """A cycle's rows: queued for the thread once started (blocks when the queue is full: back-pressure),
        else written now."""
        self.last_cycle = time.monotonic()
        if self._queue is not None:
            self._queue.put(cycle)
            return
        self.record_pods(cycle.cluster, cycle.views, cycle.bound)
        if cycle.fresh:
            self.store(cycle.cluster, cycle.plan, cycle.fresh)

    def _loop(self, writes: queue.Queue[CycleWrite | None]) -> None:
        """The writer thread: drains the queue, one ledger upsert for the batch (the latest views, every pod
        bound in it) and the decisions of each cycle; ends at ``None`` after writing what came before."""
        try:
            done = False
            while not done:
                batch = [writes.get()]
                while True:
                    try:
                        batch.append(writes.get_nowait())
                    except queue.Empty:
                        break
                done = any(item is None for item in batch)
                items = [item for item in batch if item is not None]
                if not items:
                    continue
                bound: dict = {}
                for item in items:
                    bound.update(item.bound)
                try:
                    if self._rewrite.is_set():
                        self._rewrite.clear()
                        self._recorded.clear()
                    # One commit for the batch: cycles of a pod or two each (a burst decided as it arrives) made
                    # one plan and one commit each, every commit a WAL flush on the machine the binds share.
                    with transaction.atomic():
                        self.record_pods(items[-1].cluster, items[-1].views, bound, trust_recorded=True)
                        for item in items:
                            if item.fresh:
                                self.store(item.cluster, item.plan, item.fresh)
                    self.writes += len(items)
                except Exception:  # logged and counted; the next batch writes every row that differs again
                    self.write_errors += 1
                    self._recorded.clear()
                    log.exception("RT scheduler: writing the ledger and decisions failed")
                    close_old_connections()
                if not done:  # the cycles of the next WRITE_EVERY seconds are written together (not at stop)
                    self._closing.wait(WRITE_EVERY)
        finally:
            connection.close()

    def record_pods(
        self,
        cluster: Cluster,
        views: list[PodView],
        bound: dict[tuple[str, str], tuple[str, float]] | None = None,
        trust_recorded: bool = False,
    ) -> None:
        """Upsert the ledger rows of the pods seen (``bound``: (namespace, name) -> (node, utilisation) of the
        pods this cycle bound, bound now); pods gone from the API are marked deleted. ``trust_recorded`` (the
        writer thread, which empties ``_recorded`` at each sync): the live rows are the ones last written."""
        now = timezone.now()
        bound = bound or {}
        # Each pod's ledger row first: only the rows that differ from what this process last wrote become model
        # instances (a batch of a few new pods among 1,000 built 1,000 of them).
        state: dict[tuple[str, str], LedgerRow] = {}
        for v in views:
            meta, spec = v.pod["metadata"], v.pod.get("spec") or {}
            key = (meta["namespace"], meta["name"])
            just_bound = bound.get(key)
            node = just_bound[0] if just_bound else spec.get("nodeName") or ""
            c = v.container
            containers = spec.get("containers") or [{}]
            state[key] = LedgerRow(
                uid=meta.get("uid", ""),
                node=node,
                container_name=containers[0].get("name", ""),
                scheduler_name=spec.get("schedulerName", ""),
                realtime_id=v.realtime.pk if v.realtime else None,
                criticality=c.criticality if c else (v.realtime.criticality if v.realtime else NONE),
                stateless=c.stateless if c else False,
                cpu=c.cpu if c else 0.0,
                memory_mib=c.memory_mib if c else 0.0,
                utilization=c.utilization(node) if c and node else None,
                owned=any(o.get("controller") for o in meta.get("ownerReferences") or []),
                phase=(v.pod.get("status") or {}).get("phase", ""),
                bound_at=now if just_bound else (_bound_at(v.pod) if node else None),
            )
        seen = set(state)
        rows = [
            RTPod(cluster=cluster, namespace=space, name=name, deleted_at=None, **row._asdict())
            for (space, name), row in state.items()
            if self._recorded.get((space, name)) != row
        ]
        with transaction.atomic():
            RTPod.objects.bulk_create(
                sorted(rows, key=lambda r: (r.namespace, r.name)),
                update_conflicts=True,
                unique_fields=["cluster", "namespace", "name"],
                update_fields=[*LedgerRow._fields, "deleted_at", "seen"],
            )
            live = RTPod.objects.filter(cluster=cluster, deleted_at__isnull=True)
            ns = sync.namespaces_of(cluster, self.namespace)
            if ns is not None:
                live = live.filter(namespace=ns)
            if trust_recorded and self._recorded:
                # The live rows are the ones this process last wrote (the others were marked deleted then): the
                # pods gone since are known without reading every live row back (at each sync, _recorded is
                # emptied and they are read, as for every field another writer may have changed meanwhile).
                by_space: dict[str, list[str]] = {}
                for space, name in self._recorded.keys() - seen:
                    by_space.setdefault(space, []).append(name)
                for space, names in by_space.items():
                    live.filter(namespace=space, name__in=names).update(deleted_at=now)
            else:
                gone = [pk for pk, n, name in live.values_list("pk", "namespace", "name") if (n, name) not in seen]
                if gone:
                    RTPod.objects.filter(pk__in=gone).update(deleted_at=now)
        self._recorded = {key: state[key] for key in seen}  # written (or unchanged) and committed

    def store(self, cluster: Cluster, plan, fresh: list) -> None:
        """Store the plan and the given decisions (the scheduler's new ones: outcome or reason changed)."""
        with transaction.atomic():
            row = RTPlan.objects.create(
                cluster=cluster,
                kind=RTPlan.Kind.SCHEDULER,
                plan={**plan.to_dict(), "explain": rt_kube.explain(plan)},
                placed=sum(1 for _, _, o, _ in fresh if o == RTDecision.Outcome.BOUND),
                pending=sum(1 for _, _, o, _ in fresh if o != RTDecision.Outcome.BOUND),
            )
            RTDecision.objects.bulk_create(
                RTDecision(
                    cluster=cluster,
                    plan=row,
                    namespace=v.pod["metadata"]["namespace"],
                    pod=v.pod["metadata"]["name"],
                    pod_uid=v.pod["metadata"].get("uid", ""),
                    realtime=v.realtime,
                    criticality=v.container.criticality if v.container else NONE,
                    outcome=outcome,
                    node=d.node or "",
                    score=d.score,
                    message=message[:1000],
                    decision=d.to_dict(),
                )
                for v, d, outcome, message in fresh
            )


def _bound_at(pod: dict) -> datetime | None:
    for c in (pod.get("status") or {}).get("conditions") or []:
        if c.get("type") == "PodScheduled" and c.get("status") == "True":
            return parse_time(c.get("lastTransitionTime"))
    return parse_time(pod["metadata"].get("creationTimestamp"))
