"""The secondary RT scheduler as a long-running process (thesis 3.4, Fig. 3.34; spec 03 4.4, 16.3).

``python manage.py rt_scheduler --cluster ID`` runs :meth:`RTScheduler.run`: a level-triggered loop that
wakes on relevant watch events (a pod waiting for ``schedulerName: RT-scheduler``, a pod gone or bound
elsewhere, a node changed, RealTime and Monitoring objects) or every ``period`` seconds, and in each cycle

1. lifts the monitor's node taints whose time is up;
2. reads the pods and nodes (the informer caches the watches keep, :mod:`apps.kube.informer`; listed
   when the watch is off or reconnecting), the monitor's active node taints added from the database;
3. runs the engine's RT-Kube pass (``rt_kube.schedule``: sort, filter, score) over the pending pods,
   with the bound pods' reservations in the ledger, and binds each placed pod (Binding API);
4. records the pods in the ledger (:class:`~apps.realtime.models.RTPod`) and stores each new decision
   (:class:`~apps.realtime.models.RTDecision`) with the verdict of every node on a cluster of at most
   ``rt_kube_vec.FULL_UP_TO`` nodes, else bounded: the top candidates with their scores, the count of nodes
   each filter rejected and an example of each (any node's verdict on demand: ``planning.why_not``);
5. explains every pod left pending on the pod itself (``PodScheduled`` condition and a
   ``FailedScheduling`` Event, only when the reason changes).

The RT sync (RealTime objects, node RT attributes, Monitoring counters; every ``sync_period``, or at once
after a watch event on RealTime objects) runs in its own thread while the loop runs with the watch on, and
steps 4 and 5 in background threads after the binds (see :class:`RTScheduler`): the path watch event ->
decision -> Binding holds no database write. A cycle called on its own does every step inline.

A pending pod is retried every cycle, i.e. as soon as capacity frees up (a pod deleted, a taint lifted, a
node added). A failing cycle (API unreachable, database hiccup) is logged and retried with an exponential
back-off: the process never crash-loops. Monitoring objects updated in the API are ingested by the watch
thread as soon as the API reports them (the same code path as the REST endpoint).
"""

from __future__ import annotations

import dataclasses
import logging
import queue
import sys
import threading
import time
from collections import deque
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any

from django.db import close_old_connections, connection
from django.utils import timezone

from apps.clusters.kube import api_client_for
from apps.clusters.models import Cluster, ComputeNode
from apps.kube import gateway
from apps.kube.gateway import API_ERRORS, KubeError, allocatable, node_fields
from apps.kube.informer import Informer
from apps.kube.parallel import concurrency, gather, run_bounded
from continuum.engine.core.cluster import default_rt_threshold
from continuum.engine.core.errors import InputError
from continuum.engine.core.placement import Decision
from continuum.engine.core.taints import NOT_READY, status_taint
from continuum.engine.rtkube import rt_kube, rt_kube_vec
from continuum.engine.rtkube.rt_model import (
    NONE,
    RT_LABEL,
    RT_SCHEDULER_NAME,
    RTContainer,
    RTNode,
    Taint,
    Toleration,
)

from . import metrics, monitoring, sync
from .cycle_state import CycleState
from .kube import (
    KUBE_ERRORS,
    MONITORING_GROUP,
    MONITORING_PLURAL,
    MONITORING_VERSION,
    REALTIME_GROUP,
    REALTIME_PLURAL,
    REALTIME_VERSION,
    Kube,
    binders,
    kube_for,
    parse_time,
    problem,
    requests_of,
)
from .ledger_writer import CycleWrite, LedgerWriter
from .models import MonitoringReport, RealTime, RTDecision

log = logging.getLogger("continuum.rt_scheduler")
STATELESS_LABEL = "rt.monitoring/stateless"
MAX_BACKOFF = 30.0


def pod_key(pod: dict) -> str:
    return f"{pod['metadata']['namespace']}/{pod['metadata']['name']}"


def is_terminated(pod: dict) -> bool:
    return (pod.get("status") or {}).get("phase") in ("Succeeded", "Failed") or bool(
        pod["metadata"].get("deletionTimestamp")
    )


def waits_for_us(pod: dict) -> bool:
    """Not bound yet, and named for this scheduler (terminated pods are filtered out before)."""
    spec = pod.get("spec") or {}
    return not spec.get("nodeName") and spec.get("schedulerName") == RT_SCHEDULER_NAME


def rt_nodes(cluster: Cluster, api_nodes: list[dict], rows: dict[str, ComputeNode] | None = None) -> list[RTNode]:
    """The engine's nodes: capacity and taints from the API, RT attributes from Continuum's node rows (``rows``:
    as read already, by name)."""
    rows = rows if rows is not None else {n.name: n for n in cluster.nodes.all()}
    out = []
    for obj in api_nodes:
        name = obj["metadata"]["name"]
        f = node_fields(obj)
        alloc = (obj.get("status") or {}).get("allocatable") or (obj.get("status") or {}).get("capacity") or {}
        cpu, mem = requests_of({"spec": {"containers": [{"resources": {"requests": alloc}}]}})
        taints = [Taint(t["key"], t.get("value") or "", t["effect"]) for t in f["taints"]]
        if f["status"] != ComputeNode.Status.READY:  # the rule of Cluster.to_engine, on the API's view
            status = status_taint(f["status"]) or NOT_READY
            if not any(t.key == status.key for t in taints):
                taints.append(status)
        row = rows.get(name)
        rt = bool(row and row.rt)
        cpu = cpu or (row.cpu if row else 1.0) or 1.0
        # The cluster file's threshold, else what the node's kernel admits, else M x 0.95 of the API's CPUs.
        threshold = default_rt_threshold(cpu) if row is None else row.rt_capacity_or(default_rt_threshold(cpu))
        out.append(
            RTNode(
                name,
                rt,
                (row.criticality or None) if row else None,
                cpu,
                mem or float("inf"),
                threshold,
                tuple(taints),
                f["labels"],
            )
        )
    return out


def tolerations_of(pod: dict) -> tuple[Toleration, ...]:
    out = []
    for t in (pod.get("spec") or {}).get("tolerations") or []:
        try:
            out.append(Toleration.parse(t, pod_key(pod)))
        except InputError:
            continue  # a toleration the API accepted but we do not model (e.g. tolerationSeconds only)
    return tuple(out)


@dataclass
class PodView:
    """What the scheduler knows of one pod: its JSON, its RealTime (if any) and the engine container."""

    pod: dict
    realtime: RealTime | None
    container: RTContainer | None
    problem: str = ""

    @property
    def key(self) -> str:
        return pod_key(self.pod)


def view_pod(
    pod: dict,
    realtimes: dict[tuple[str, str], RealTime],
    known_nodes: list[str],
    engines: dict[tuple[str, str], RTContainer | InputError] | None = None,
) -> PodView:
    """``engines``: a memo of each RealTime's engine container (many pods name the same RealTime)."""
    meta = pod["metadata"]
    labels = meta.get("labels") or {}
    cpu, mem = requests_of(pod)
    created = parse_time(meta.get("creationTimestamp"))
    arrival = created.timestamp() if created else 0.0
    stateless_label = labels.get(STATELESS_LABEL) == "true"
    rt_name = labels.get(RT_LABEL)
    tolerations = tolerations_of(pod)
    if not rt_name:
        c = RTContainer(pod_key(pod), NONE, stateless=stateless_label, cpu=cpu, memory_mib=mem,
                        tolerations=tolerations, arrival=arrival)  # fmt: skip
        return PodView(pod, None, c)
    row = realtimes.get((meta["namespace"], rt_name))
    if row is None:
        return PodView(pod, None, None, f"RealTime {rt_name!r} not found in namespace {meta['namespace']!r}")
    key = (meta["namespace"], rt_name)
    base = engines.get(key) if engines is not None else None
    if base is None:
        try:
            base = row.to_engine(known_nodes)
        except InputError as exc:
            base = exc
        if engines is not None:
            engines[key] = base
    if isinstance(base, InputError):
        return PodView(pod, row, None, f"RealTime {rt_name!r} is invalid: {base}")
    c = RTContainer(
        pod_key(pod),
        base.criticality,
        base.period,
        base.deadline,
        base.wcet,
        base.stateless or stateless_label,
        cpu or base.cpu,
        mem or base.memory_mib,
        tolerations,
        arrival,
    )
    return PodView(pod, row, c)


def pending_message(decision: Decision, total: int) -> str:
    """Every node's reason when the decision has them all; on a large cluster, as kube-scheduler says it,
    how many nodes each filter rejected (the per-node reasons are on demand: the decision's why-not)."""
    head = f"0/{total} nodes are available to {RT_SCHEDULER_NAME}: "
    if decision.rejections:
        return head + ", ".join(f"{count} {name}" for name, count in sorted(decision.rejections.items())) + "."
    reasons = decision.reasons()
    return head + "; ".join(f"{node}: {why}" for node, why in sorted(reasons.items()))


def pod_relevant(old: dict | None, new: dict | None) -> bool:
    """Whether a pod's change may change a scheduling decision (the watch wakes the loop only then): a pod
    waiting for this scheduler, a pod gone or terminated (capacity freed), a pod bound by someone else."""
    if new is None:
        return True
    spec = new.get("spec") or {}
    if is_terminated(new):
        return old is None or not is_terminated(old)
    if not spec.get("nodeName"):
        return spec.get("schedulerName") == RT_SCHEDULER_NAME
    return old is None or (old.get("spec") or {}).get("nodeName") != spec.get("nodeName")


def node_relevant(old: dict | None, new: dict | None) -> bool:
    """A node added, removed, or changed in what the filters read (not its heartbeats)."""
    if old is None or new is None:
        return True
    return (node_fields(old), allocatable(old)) != (node_fields(new), allocatable(new))


@dataclass
class CycleResult:
    bound: list[tuple[str, str]] = field(default_factory=list)
    pending: dict[str, str] = field(default_factory=dict)
    failed: dict[str, str] = field(default_factory=dict)
    lifted: int = 0
    synced: dict[str, Any] | None = None


@dataclass
class _Decided:
    """What a cycle decided, kept until its Bindings answered (see RTScheduler._conclude)."""

    cluster: Cluster
    kube: Kube
    plan: Any
    by_key: dict[str, PodView]
    pending: list[PodView]
    views: list[PodView]
    total: int


#: The GIL's switch interval while run() loops with the watch (Python's default: 5 ms). The Binding threads and the
#: pod watch thread mostly wait for the API; when an answer or an event arrives, the thread waits for the GIL
#: behind the deciding loop or the writer for up to one interval, on the pod's clock.
SWITCH_INTERVAL = 0.001
#: Per-pod timings kept for the benchmark (the latest ones).
TIMINGS = 20_000


class RTScheduler:
    """One cluster's RT scheduler (see the module docstring). ``namespace``: None = the cluster's, ``"*"`` = all.

    While :meth:`run` loops with the watch on, the path from a pod's watch event to its Binding is kept free
    of anything else, as kube-scheduler's is:

    - nodes and pods are read from informer caches filled by the watches (:mod:`apps.kube.informer`),
      not listed per cycle; a cycle starts as soon as a relevant event arrives (no period to wait for), and
      takes every pod pending by then (a burst is decided together);
    - the Bindings go out on a persistent pool of ``kube.binders()`` threads sharing one
      client; a bound pod is assumed bound in the cache until deleted, so it is never bound twice;
    - the RT sync (RealTime objects, node attributes, Monitoring counters) runs in its own thread, and it (or
      the RealTime watch, for a RealTime event) reads the RealTime rows for the next cycle;
    - the monitor's active taints are read by an rt-taints thread as soon as the pod watch reports a new
      pending pod, and the cycle's state (cluster, policy, node rows) before it is due: a deciding cycle holds
      no database read;
    - the ledger rows and the decisions ("why" of the dashboard) are written after the binds by the writer
      thread of :mod:`apps.realtime.ledger_writer`;
    - Events and pending explanations are sent in the background.

    A cycle called on its own (``--once``, tests) does all of it inline, listing from the API.
    """

    def __init__(
        self,
        cluster_id: int,
        namespace: str | None = None,
        period: float = 1.0,
        sync_period: float = 5.0,
        watch: bool = True,
        on_cycle: Callable[[CycleResult], None] | None = None,
    ) -> None:
        self.cluster_id = cluster_id
        self.namespace = namespace
        self.period = period
        self.sync_period = sync_period
        self.use_watch = watch
        self.on_cycle = on_cycle
        self.wake = threading.Event()
        self.sync_due = threading.Event()
        self.sync_due.set()
        self.stopping = threading.Event()
        self.last_sync = 0.0
        self.cycles = 0
        self.errors = 0
        self.last_error = ""
        self.explained: dict[str, str] = {}  # pod uid -> last message told to the pod
        self.threads: list[threading.Thread] = []
        self._watches = gateway.Watches()
        self.ingested = 0
        #: The informer caches (filled while run() loops with the watch on; else the cycle lists the API).
        self.pods = Informer(pod_relevant)
        self.nodes = Informer(node_relevant)
        #: While run() loops: the Events and pending explanations of a cycle are sent from this one thread
        #: (each batch with its calls overlapping) while the next cycle already decides and binds, as
        #: kube-scheduler's event broadcaster does. A cycle called on its own sends them before returning.
        self._explainer: ThreadPoolExecutor | None = None
        #: While run() loops: the Binding threads (warm, one client); the writer of rows (see the class doc).
        self._binder: ThreadPoolExecutor | None = None
        self.ledger = LedgerWriter(namespace)
        #: Pipelined mode: (decided cycle, its binds, why they stopped) once a cycle's last Binding answered.
        self._done: queue.SimpleQueue = queue.SimpleQueue()
        self._background_sync = False
        #: The views memo (see _views): its key (RealTime generation, node names), the rows, engines and views.
        self._rt_generation = 0
        #: The RealTime rows read off the loop (by the sync and RealTime watch threads, see _reload_realtimes):
        #: (the generation they are current for, their content, the rows); the lock orders bumps and publishing.
        self._rt_lock = threading.Lock()
        self._rt_loaded: tuple[int, tuple, dict[tuple[str, str], RealTime]] | None = None
        self._rt_content: tuple | None = None
        self._kube_of: tuple[Cluster, Kube] | None = None
        #: The cluster, its policy, node rows and monitor taints (read ahead by a thread while run() loops).
        self.state = CycleState(cluster_id, period)
        self._memo_key: tuple | None = None
        self._realtimes: dict[tuple[str, str], RealTime] = {}
        self._engines: dict[tuple[str, str], RTContainer | InputError] = {}
        self._memo: dict[str, tuple[tuple, PodView]] = {}
        #: Cycles that listed nodes and pods from the API (the informers were not in sync).
        self.api_reads = 0
        #: pod key -> monotonic time the watch first reported it pending (the start of its latency).
        self._seen: dict[str, float] = {}
        #: Per bound pod: (seen -> decided, decided -> Binding sent, Binding sent -> answered) in seconds.
        self.timings: deque[tuple[float, float, float]] = deque(maxlen=TIMINGS)

    # ---- the loop --------------------------------------------------------------------------------------------
    def run(self, stop: threading.Event | None = None, max_cycles: int | None = None) -> int:
        """Cycle until ``stop`` is set (or ``max_cycles`` ran); never raises for a failing cycle."""
        stop = stop or self.stopping
        failures = 0
        switch = sys.getswitchinterval()
        if self.use_watch:
            sys.setswitchinterval(min(switch, SWITCH_INTERVAL))
        self._explainer = ThreadPoolExecutor(max_workers=1, thread_name_prefix="rt-explain")
        # More than a push's bound (kube.binders): a Binding is one short write, and binds queued here wait with
        # their pods; the threads wait for the API, not for the GIL.
        self._binder = ThreadPoolExecutor(max_workers=binders(), thread_name_prefix="rt-bind")
        if self.use_watch:
            self._warm_binders()
        self.ledger.start()
        if self.use_watch:
            self._start_watches(stop)
            self._background_sync = True
            t = threading.Thread(target=self._sync_loop, args=(stop,), daemon=True, name="rt-sync")
            t.start()
            self.threads.append(t)
            self.threads.append(self.state.start(stop))
        try:
            while not stop.is_set():
                wait = self.period
                self.wake.clear()  # events from here on wake the next cycle (this one reads the cache after)
                try:
                    result = self.cycle()
                    failures = 0
                    if self.on_cycle:
                        self.on_cycle(result)
                    if self.state.expiry_at is not None:
                        wait = min(wait, max(0.0, self.state.expiry_at - time.monotonic()) + 0.01)
                except Exception as exc:  # a failing cycle must never end the process
                    failures += 1
                    self.errors += 1
                    metrics.cycle_failed()
                    self.last_error = problem(exc)
                    wait = min(MAX_BACKOFF, self.period * 2**failures)
                    log.warning("RT scheduler cycle failed (%s); retrying in %.1f s", self.last_error, wait)
                    close_old_connections()
                self.cycles += 1
                if max_cycles is not None and self.cycles >= max_cycles:
                    break
                self.wake.wait(wait)
        finally:
            stop.set()
            self.stopping.set()
            self._binder.shutdown(wait=True)
            self._binder = None
            try:  # the outcomes of the last Bindings: recorded and explained before the threads end
                self._conclude_finished(CycleResult())
            except Exception as exc:
                log.warning("RT scheduler: concluding the last binds failed (%s)", problem(exc))
            self._explainer.shutdown(wait=True)  # the explanations of the last cycle are sent
            self._explainer = None
            self.ledger.stop()  # the writer stores what is queued, then ends
            self._background_sync = False
            self.state.stop()
            self._close_watches()
            deadline = time.monotonic() + 10
            for t in self.threads:
                t.join(timeout=max(0.0, deadline - time.monotonic()))
            connection.close()
            sys.setswitchinterval(switch)
        return self.cycles

    def _warm_binders(self) -> None:
        """Each Binding thread opens its connection now, with one cheap read at once (the API's version): the
        first burst of pods otherwise paid a thread start and a TLS handshake per Binding on its clock."""
        try:
            kube = kube_for(Cluster.objects.get(pk=self.cluster_id))
        except (Cluster.DoesNotExist, *KUBE_ERRORS) as exc:
            log.info("RT scheduler: Binding connections not warmed: %s", exc)
            return

        def one() -> None:
            try:
                kube.version(retried=False)
            except KUBE_ERRORS as exc:  # the API is down: the first cycle says so
                log.debug("warming a Binding connection: %s", problem(exc))

        assert self._binder is not None
        for _ in range(binders()):
            self._binder.submit(one)

    def _close_watches(self) -> None:
        """Interrupt the watch connections (a blocked read would otherwise wait for the server's timeout)."""
        self._watches.close_all()

    def _sync(self, cluster: Cluster, kube: Kube) -> dict[str, Any]:
        self.sync_due.clear()
        before = self._rt_generation
        read: dict[tuple[str, str], RealTime] = {}
        # While run() loops the node informer has the nodes (a list of every node's full status per sync was
        # most of a sync pass on a cluster of hollow nodes); it is a watch behind at most, as a list is a moment.
        informed = self._background_sync and self.nodes.synced
        synced = {
            "nodes": sync.sync_node_rt(cluster, kube, self.nodes.snapshot() if informed else None),
            "realtimes": sync.sync_realtimes(cluster, kube, self.namespace, rows_read=read),
            "monitorings": sync.push_monitorings(cluster, kube),
        }
        self.last_sync = time.monotonic()
        generation = self._bump_realtimes()  # the RealTime rows are read again
        if self._background_sync:  # here, not on the next cycle's clock
            part = synced["realtimes"]
            if generation == before + 1 and not any(
                part[k] for k in ("read", "updated", "pushed", "deleted", "errors")
            ):
                self._publish_realtimes(generation, read)  # the sync's own read, no change since: current
            else:
                self._reload_realtimes(cluster, generation)
        self.ledger.rewrite_all()
        return synced

    def _bump_realtimes(self) -> int:
        """The RealTime rows may have changed: the next cycle's views use rows read after this (a new generation)."""
        with self._rt_lock:
            self._rt_generation += 1
            return self._rt_generation

    def _load_realtimes(self, cluster: Cluster) -> dict[tuple[str, str], RealTime]:
        rows = cluster.realtimes.prefetch_related("wcets__node")
        ns = sync.namespaces_of(cluster, self.namespace)
        if ns is not None:
            rows = rows.filter(namespace=ns)
        return {(r.namespace, r.name): r for r in rows}

    def _reload_realtimes(self, cluster: Cluster, generation: int) -> None:
        """Read the RealTime rows for ``generation`` (a thread off the loop's path: the read, with each row's WCETs,
        took ~17 ms of the first cycle after every sync and RealTime event); kept only if no change came since."""
        self._publish_realtimes(generation, self._load_realtimes(cluster))

    def _publish_realtimes(self, generation: int, rows: dict[tuple[str, str], RealTime]) -> None:
        content = _realtimes_content(rows)
        with self._rt_lock:
            if self._rt_generation == generation:
                self._rt_loaded = (generation, content, rows)

    def _sync_loop(self, stop: threading.Event) -> None:
        """The RT sync in its own thread while run() loops (off the path watch -> decide -> bind); a cycle
        follows each sync (a RealTime may have arrived for a pending pod)."""
        failures = 0
        try:
            while not stop.is_set():
                due = self.sync_due.is_set() or time.monotonic() - self.last_sync >= self.sync_period
                if due:
                    try:
                        cluster = Cluster.objects.get(pk=self.cluster_id)
                        self._sync(cluster, kube_for(cluster))
                        failures = 0
                        self.wake.set()
                    except Exception as exc:  # retried with back-off, as a failing cycle
                        failures += 1
                        self.errors += 1
                        self.last_error = problem(exc)
                        log.warning("RT sync failed (%s)", self.last_error)
                        close_old_connections()
                        stop.wait(min(MAX_BACKOFF, self.period * 2**failures))
                        continue
                left = self.sync_period - (time.monotonic() - self.last_sync)
                self.sync_due.wait(max(0.01, min(left, 1.0)))
        finally:
            connection.close()

    def _read(self, kube: Kube, ns: str | None) -> tuple[list[dict], list[dict]]:
        """Nodes and pods: from the informers when both are in sync, else listed (two reads at once)."""
        if self.use_watch and self._background_sync and self.pods.synced and self.nodes.synced:
            return self.nodes.snapshot(), self.pods.snapshot()
        self.api_reads += 1
        api_nodes, pods = gather(kube.list_nodes, lambda: kube.list_pods(ns))
        return api_nodes, pods

    def _monitor_taints(self, nodes: list[RTNode], need: float) -> list[RTNode]:
        """The nodes with the monitor's active taints added from the database. The monitor taints a node in the
        API, commits the taint's row, then creates the evicted pod's replacement: the pod watch may report the
        replacement before the node watch reports the taint (two streams), the committed row is already there
        for a read started after the pod's event (``need``, see CycleState.active_taints)."""
        active: dict[str, list[Taint]] = {}
        now = timezone.now()
        for name, key, value, effect, expires in self.state.active_taints(need):
            if expires > now:  # as a read now would filter them
                active.setdefault(name, []).append(Taint(key, value, effect))
        if not active:
            return nodes
        out = []
        for n in nodes:
            extra = [
                t for t in active.get(n.name, []) if not any((t.key, t.effect) == (h.key, h.effect) for h in n.taints)
            ]
            out.append(dataclasses.replace(n, taints=(*n.taints, *extra)) if extra else n)
        return out

    def cycle(self) -> CycleResult:
        began = time.monotonic()
        cluster, policy, rows = self.state.get()
        kube = self._kube(cluster)
        result = CycleResult()
        self._conclude_finished(result)
        if not self._background_sync or (self.state.expiry_at is not None and began >= self.state.expiry_at):
            result.lifted = monitoring.lift_expired_taints(cluster)
            if self._background_sync:
                cluster, policy, rows = self.state.get(fresh=True)  # the node rows lost the taint
        if not self._background_sync and (
            self.sync_due.is_set() or time.monotonic() - self.last_sync >= self.sync_period
        ):
            result.synced = self._sync(cluster, kube)
        ns = sync.namespaces_of(cluster, self.namespace)
        if (
            self.ledger.threaded
            and self._background_sync
            and self.pods.synced
            and time.monotonic() - self.ledger.last_cycle < self.period
            and not any(waits_for_us(p) and not is_terminated(p) for p in self.pods.snapshot())
        ):
            return result  # nothing to decide; the ledger rows are written at most once a period meanwhile
        api_nodes, pods = self._read(kube, ns)
        pods = [p for p in pods if not is_terminated(p)]
        nodes = rt_nodes(cluster, api_nodes, rows)
        names = [n.name for n in nodes]
        views = self._views(cluster, ns, pods, names)
        pending = [v for v in views if waits_for_us(v.pod)]
        metrics.waiting(len(pending))
        if not pending:
            self.ledger.write(CycleWrite(cluster, views, {}, None, []))
            return result
        if self._background_sync:
            now = time.monotonic()
            nodes = self._monitor_taints(nodes, max(self._seen.get(v.key, now) for v in pending))
        known = set(names)
        ledger = rt_kube.Ledger.with_reservations(
            nodes,
            (
                (v.container, node)
                for v in views
                if v.container is not None and (node := (v.pod.get("spec") or {}).get("nodeName")) in known
            ),
        )
        schedulable = [v for v in pending if v.container is not None]
        # The vectorised pass (same choices as rt_kube.schedule); explanations bounded past FULL_UP_TO nodes.
        plan = rt_kube_vec.schedule(
            [v.container for v in schedulable], nodes, policy.scheduler_params(), ledger, now=time.time(), full="auto"
        )
        decided = time.monotonic()
        by_key = {v.key: v for v in pending}
        placed = [(by_key[d.item], d) for d in plan.decisions if d.node is not None]
        metrics.attempted(decided - began, len(placed), len(pending) - len(placed))
        cycle = _Decided(cluster, kube, plan, by_key, pending, views, len(nodes))
        if self._pipelined():
            # The Bindings go out and the loop goes on (kube-scheduler's assume, then bind asynchronously): the
            # pods are assumed bound at once, so the next cycle's ledger holds them; the outcomes are concluded
            # by the cycle after the last Binding answered.
            for v, d in placed:
                self.pods.assume(v.key, v.pod["metadata"].get("uid", ""), d.node or "")
            if not placed:
                self._conclude(cycle, {}, None, result)
            else:
                self._bind_async(kube, placed, decided, lambda binds, stopped: self._done.put((cycle, binds, stopped)))
        else:
            binds, stopped = self._bind_all(kube, placed, decided)
            self._conclude(cycle, binds, stopped, result)
        log.debug("RT cycle: %d pending, %d bound in %.3f s", len(pending), len(result.bound), time.monotonic() - began)
        return result

    def _kube(self, cluster: Cluster) -> Kube:
        """``kube_for(cluster)``, remembered while the cycle state keeps the same cluster row (``kube_for`` hashes the
        kubeconfig, which releases and takes back the GIL: ~1.5 ms of each cycle on a busy machine)."""
        if self._kube_of is None or self._kube_of[0] is not cluster:
            self._kube_of = (cluster, kube_for(cluster))
        return self._kube_of[1]

    def _pipelined(self) -> bool:
        return self._binder is not None and self._background_sync

    def _conclude_finished(self, result: CycleResult) -> None:
        """The outcomes of every earlier cycle whose Bindings all answered (pipelined mode)."""
        stopped = None
        while True:
            try:
                cycle, binds, why = self._done.get_nowait()
            except queue.Empty:
                break
            try:
                self._conclude(cycle, binds, why, result)
            except KubeError as exc:
                stopped = stopped or exc
        if stopped is not None:
            raise stopped

    def _conclude(self, cycle: _Decided, binds: dict, stopped: str | None, result: CycleResult) -> None:
        """A cycle's outcomes once its Bindings answered: the result, the rows (off the path from the watch
        event to the Binding: the writer thread while run() loops; which decisions are new is judged here,
        before _explain marks them told) and the explanations."""
        outcomes, bound_rows = [], {}
        for d in cycle.plan.decisions:
            v = cycle.by_key[d.item]
            if d.node is None:
                message = pending_message(d, cycle.total)
                outcomes.append((v, d, RTDecision.Outcome.PENDING, message))
                result.pending[v.key] = message
                continue
            ok, message = binds[d.item]
            if ok is None:  # not attempted: the API went away during this cycle's binds (raised below)
                continue
            if ok:
                result.bound.append((v.key, d.node))
                outcomes.append((v, d, RTDecision.Outcome.BOUND, message))
                meta = v.pod["metadata"]
                bound_rows[(meta["namespace"], meta["name"])] = (d.node, v.container.utilization(d.node))
            else:
                result.failed[v.key] = message
                outcomes.append((v, d, RTDecision.Outcome.FAILED, message))
        for v in cycle.pending:
            if v.container is None:
                d = Decision(v.key, None)
                result.pending[v.key] = v.problem
                outcomes.append((v, d, RTDecision.Outcome.PENDING, v.problem))
        self.ledger.write(CycleWrite(cycle.cluster, cycle.views, bound_rows, cycle.plan, self._fresh(outcomes)))
        self._explain(cycle.kube, outcomes)
        if stopped:  # the pods bound before it are recorded; the cycle fails and is retried with back-off
            raise KubeError(stopped)

    def _views(self, cluster: Cluster, ns: str | None, pods: list[dict], names: list[str]) -> list[PodView]:
        """Each pod's view, remembered from the last cycle while the pod (uid, resourceVersion, node), the node
        names and the RealTime rows are the same: a cycle for a few new pods does not parse the bound ones
        again. The RealTime rows are read again after each sync and each RealTime event (while run() loops, by
        the thread that saw it: the cycle reads them only if a newer change came meanwhile; every cycle when the
        cycle runs on its own); rows read again with the same content keep the views."""
        if not self._background_sync:
            self._bump_realtimes()
        generation = self._rt_generation
        memo_key = (generation, tuple(names))
        if self._memo_key != memo_key:
            loaded = self._rt_loaded
            if loaded is not None and loaded[0] == generation:
                _, content, rows = loaded  # read after the change, by the sync or RealTime watch thread
            else:
                rows = self._load_realtimes(cluster)
                content = _realtimes_content(rows)
            # Rows read again but equal (every sync reads them): the views and engines built from them stay.
            if self._memo_key is None or content != self._rt_content or memo_key[1] != self._memo_key[1]:
                self._realtimes = rows
                self._rt_content = content
                self._engines = {}
                self._memo = {}
            self._memo_key = memo_key
        memo: dict[str, tuple[tuple, PodView]] = {}
        views = []
        for p in pods:
            meta = p["metadata"]
            key = pod_key(p)
            ident = (meta.get("uid"), meta.get("resourceVersion"), (p.get("spec") or {}).get("nodeName"))
            known = self._memo.get(key)
            if known is not None and known[0] == ident:
                view = known[1]
                if view.pod is not p:
                    view = PodView(p, view.realtime, view.container, view.problem)
            else:
                view = view_pod(p, self._realtimes, names, self._engines)
            memo[key] = (ident, view)
            views.append(view)
        self._memo = memo
        return views

    def _bind_all(
        self, kube: Kube, placed: list[tuple[PodView, Decision]], decided: float | None = None
    ) -> tuple[dict, str | None]:
        """The bind phase of every placed pod, at most ``CONTINUUM_KUBE_PUSH_CONCURRENCY`` Bindings in flight
        (the decisions are all made: binds are independent round trips). {pod key: (ok, message)} with
        ``ok=None`` for the binds not attempted after the API failed (the reason is returned). A pod bound is
        assumed bound in the pod cache at once (see :mod:`apps.kube.informer`)."""
        decided = decided if decided is not None else time.monotonic()
        reason: list[str] = []
        lock = threading.Lock()

        def one(item: tuple[PodView, Decision]) -> tuple[bool | None, str]:
            return self._bind_one(kube, item, decided, reason, lock)

        if self._binder is None:
            results, stopped = run_bounded(placed, one, skipped=lambda r: (None, r), fatal=(), describe=problem)
        else:
            futures = [self._binder.submit(one, item) for item in placed]
            results, stopped = [f.result() for f in futures], None
        stopped = stopped or (reason[0] if reason else None)
        return {d.item: r for (_, d), r in zip(placed, results, strict=True)}, stopped

    def _bind_one(
        self, kube: Kube, item: tuple[PodView, Decision], decided: float, reason: list[str], lock: threading.Lock
    ) -> tuple[bool | None, str]:
        """One pod's Binding, shared by the cycle's two ways of binding. Once the API failed (``reason`` holds
        why) the rest are not attempted (``None``); a bound pod is assumed bound in the pod cache at once and
        its timings (event -> decided -> sent -> answered) are kept."""
        v, d = item
        meta, node = v.pod["metadata"], d.node or ""
        if reason:
            return None, reason[0]
        sent = time.monotonic()
        try:
            ok, message = kube.bind(meta["namespace"], meta["name"], node, meta.get("uid"))
        except API_ERRORS as exc:
            metrics.bound(time.monotonic() - sent, False)
            with lock:
                if not reason:
                    reason.append(problem(exc))
            return None, reason[0]
        metrics.bound(time.monotonic() - sent, ok)
        if ok:
            self.pods.assume(v.key, meta.get("uid", ""), node)
            answered = time.monotonic()
            seen = self._seen.pop(v.key, decided)
            self.timings.append((decided - seen, sent - decided, answered - sent))
        return ok, message

    def _bind_async(self, kube: Kube, placed: list[tuple[PodView, Decision]], decided: float, finished) -> None:
        """The Bindings of a cycle on the binder pool, without waiting; ``finished(binds, stopped)`` is called
        (in a binder thread) when the last one answered. A failed Binding un-assumes its pod (pending again)."""
        left = [len(placed)]
        binds: dict[str, tuple[bool | None, str]] = {}
        reason: list[str] = []
        lock = threading.Lock()

        def one(item: tuple[PodView, Decision]) -> None:
            v, d = item
            ok: bool | None
            try:
                ok, message = self._bind_one(kube, item, decided, reason, lock)
            except Exception as exc:  # a bug: the pod is retried, the cycle's outcome says why
                log.exception("RT scheduler: binding %s failed", v.key)
                ok, message = False, f"binding failed: {exc}"
            if not ok:
                self.pods.forget(v.key, v.pod["metadata"].get("uid", ""))
            with lock:
                binds[d.item] = (ok, message)
                left[0] -= 1
                last = left[0] == 0
            if last:
                finished(binds, reason[0] if reason else None)
                self.wake.set()

        assert self._binder is not None
        for item in placed:
            self._binder.submit(one, item)

    # ---- bookkeeping ---------------------------------------------------------------------------------------
    def _fresh(self, outcomes: list) -> list:
        """The decisions whose outcome or reason changed since the pod's last one (the others are not stored)."""
        fresh = []
        for v, d, outcome, message in outcomes:
            uid = v.pod["metadata"].get("uid", "")
            if outcome == RTDecision.Outcome.PENDING and self.explained.get(uid) == message:
                continue
            fresh.append((v, d, outcome, message))
        return fresh

    def _explain(self, kube: Kube, outcomes: list) -> None:
        """A ``Scheduled`` Event per bound pod, the reason on each pod left pending (when it changed); the
        calls overlap, at most ``CONTINUUM_KUBE_PUSH_CONCURRENCY`` in flight (one round trip each). While
        :meth:`run` loops they are sent in the background (see ``_explainer``)."""
        calls = []
        for v, d, outcome, message in outcomes:
            uid = v.pod["metadata"].get("uid", "")
            if outcome == RTDecision.Outcome.BOUND:
                self.explained.pop(uid, None)
                calls.append((v, "Scheduled", f"Successfully assigned {v.key} to {d.node}"))
            elif self.explained.get(uid) != message:
                # Told once: marked now (the next cycle must not queue it again), unmarked if it fails.
                self.explained[uid] = message
                calls.append((v, "", message))
        if not calls:
            return
        if self._explainer is not None:
            self._explainer.submit(self._send_explanations, kube, calls)
        else:
            self._send_explanations(kube, calls)

    def _send_explanations(self, kube: Kube, calls: list[tuple[PodView, str, str]]) -> None:
        def one(item: tuple[PodView, str, str]) -> None:
            v, reason, message = item
            try:
                if reason:
                    kube.event(v.pod, reason, message)
                else:
                    kube.explain_pending(v.pod, message)
            except KUBE_ERRORS as exc:
                log.info("%s for %s: %s", "no Scheduled event" if reason else "cannot explain", v.key, exc)
                uid = v.pod["metadata"].get("uid", "")
                if not reason and self.explained.get(uid) == message:
                    del self.explained[uid]  # told again at the next cycle

        try:
            # A quarter of the bound: the next cycle's Bindings share the client's connection pool.
            run_bounded(calls, one, skipped=lambda reason: None, fatal=(), describe=problem,
                        workers=max(1, concurrency() // 4))  # fmt: skip
        except Exception:  # a bug in the background must not be lost silently
            log.exception("RT scheduler explanations failed")
            if self._explainer is None:
                raise

    # ---- watches ----------------------------------------------------------------------------------------------
    def _start_watches(self, stop: threading.Event) -> None:
        for target in (self._watch_pods, self._watch_nodes, self._watch_realtimes, self._watch_monitorings):
            t = threading.Thread(target=self._follow, args=(target, stop), daemon=True, name=target.__name__)
            t.start()
            self.threads.append(t)

    def _follow(self, target, stop: threading.Event) -> None:
        """One watch thread: ``target(cluster)`` names what to follow, what to do with each event and, for an
        informer, with each list (``None``: no list); the gateway's watch loop resumes it, starts over after
        410 Gone and comes back after any failure (with exponential backoff) until ``stop``. The cluster is
        read again on every reconnection, and an informer is marked stale until its next list."""
        handlers: dict[str, Any] = {}

        def connect():
            cluster = Cluster.objects.get(pk=self.cluster_id)
            handlers["pick"], handlers["on_event"], handlers["on_list"], handlers["informer"] = target(cluster)
            if handlers["informer"] is not None:
                handlers["informer"].unsynced()
            return api_client_for(cluster)

        informer = target in (self._watch_pods, self._watch_nodes)  # listed first, then watched
        try:
            gateway.follow(
                connect,
                lambda api_client: handlers["pick"](api_client),
                lambda event: handlers["on_event"](event),
                on_list=(lambda items: handlers["on_list"](items)) if informer else None,
                stop=stop,
                retries=None,
                backoff=1.0,
                max_backoff=MAX_BACKOFF,
                watch_seconds=20,
                what=f"RT scheduler {target.__name__}",
                watches=self._watches,
                retry_on=(Exception,),
            )
        finally:
            connection.close()

    def _watch_pods(self, cluster: Cluster):
        """Every pod of the namespace (the ledger counts pods of other schedulers on RT nodes too)."""
        pick = gateway.watch_pods(sync.namespaces_of(cluster, self.namespace))

        def listed(items: list[dict]) -> None:
            now = time.monotonic()
            for p in items:
                if pod_relevant(None, p) and not (p.get("spec") or {}).get("nodeName"):
                    self._seen.setdefault(pod_key(p), now)
            self.pods.replace(items)
            self.state.ask_taints(now)
            self.wake.set()

        def changed(event: dict) -> None:
            if self.pods.apply(event):
                obj = event.get("raw_object") or {}
                key = pod_key(obj) if obj.get("metadata") else ""
                if event.get("type") == "DELETED":
                    self._seen.pop(key, None)
                elif (
                    key and key not in self._seen and not (obj.get("spec") or {}).get("nodeName")
                ) and not is_terminated(obj):
                    now = time.monotonic()
                    self._seen[key] = now
                    self.state.ask_taints(now)  # read while the loop wakes (see CycleState)
                self.wake.set()

        return pick, changed, listed, self.pods

    def _watch_nodes(self, cluster: Cluster):
        def listed(items: list[dict]) -> None:
            self.nodes.replace(items)
            self.wake.set()

        def changed(event: dict) -> None:
            if self.nodes.apply(event):
                self.wake.set()

        return gateway.watch_nodes(), changed, listed, self.nodes

    def _custom(self, cluster: Cluster, group: str, version: str, plural: str):
        return gateway.watch_custom_objects(group, version, plural, sync.namespaces_of(cluster, self.namespace))

    def _watch_realtimes(self, cluster: Cluster):
        def changed(event: dict) -> None:
            generation = self._bump_realtimes()  # a RealTime changed (here or there): its rows are read again
            obj = event.get("raw_object") or {}
            meta = obj.get("metadata") or {}
            rv = meta.get("resourceVersion")
            known = RealTime.objects.filter(
                cluster_id=self.cluster_id, namespace=meta.get("namespace"), name=meta.get("name"), resource_version=rv
            ).exists()
            if event.get("type") == "DELETED" or not known:
                self.sync_due.set()  # the sync thread reads the rows after it
                self.wake.set()
            else:  # the row has this version already: read here, not by the next cycle
                self._reload_realtimes(cluster, generation)

        return self._custom(cluster, REALTIME_GROUP, REALTIME_VERSION, REALTIME_PLURAL), changed, None, None

    def _watch_monitorings(self, cluster: Cluster):
        def changed(event: dict) -> None:
            if event.get("type") not in ("ADDED", "MODIFIED"):
                return
            obj = event["raw_object"]
            try:
                self.ingest_object(cluster, obj)
            except InputError as exc:
                meta = obj.get("metadata") or {}
                log.info("Monitoring %s/%s rejected: %s", meta.get("namespace"), meta.get("name"), exc)
                self._status(cluster, obj, {"error": str(exc)})

        return self._custom(cluster, MONITORING_GROUP, MONITORING_VERSION, MONITORING_PLURAL), changed, None, None

    def ingest_object(self, cluster: Cluster, obj: dict) -> dict | None:
        """A Monitoring object changed in the API: a report, unless it only shows the counters we stored."""
        report = monitoring.parse_report(obj, 0)
        rv = (obj.get("metadata") or {}).get("resourceVersion", "")
        if sync.own_write(cluster, report.name, rv):
            return None
        row = cluster.monitorings.filter(name=report.name).select_related("node").first()
        if row is not None and rv and row.resource_version == rv:
            return None
        if (
            row is not None
            and row.node.name == report.node
            and row.container_name == report.container
            and (row.missed_period, row.missed_total) == (report.missed_period, report.missed_total)
        ):
            return None
        result = monitoring.ingest(cluster, [report], MonitoringReport.Source.KUBE)
        self.ingested += 1
        action = result["events"][0] if result["events"] else None
        status = {
            "lastReport": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%S.%fZ"),
            "violation": bool(result["violations"]),
            "action": (f"evicted {action['victim']}" if action and action["victim"] else action["kind"])
            if action
            else "none",
        }
        self._status(cluster, obj, status)
        return result

    def _status(self, cluster: Cluster, obj: dict, status: dict) -> None:
        meta = obj.get("metadata") or {}
        try:
            kube_for(cluster).patch_status(
                MONITORING_GROUP, MONITORING_VERSION, MONITORING_PLURAL, meta["namespace"], meta["name"], status
            )
        except (*KUBE_ERRORS, KeyError) as exc:
            log.info("cannot write the status of Monitoring %s: %s", meta.get("name"), exc)


def _realtimes_content(rows: dict[tuple[str, str], RealTime]) -> tuple:
    """What the views and engine containers are built from, per RealTime row (equal content: same views)."""
    return tuple(
        (key, r.pk, r.criticality, r.period, r.deadline, r.stateless, r.cpu, r.memory_mib, tuple(r.wcet_pairs()))
        for key, r in sorted(rows.items())
    )
