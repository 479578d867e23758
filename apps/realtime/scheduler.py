"""The secondary RT scheduler as a long-running process (thesis 3.4, Fig. 3.34; spec 03 4.4, 16.3).

``python manage.py rt_scheduler --cluster ID`` runs :meth:`RTScheduler.run`: a level-triggered loop that
wakes on watch events (pods with ``schedulerName: RT-scheduler``, RealTime and Monitoring objects) or
every ``period`` seconds, and in each cycle

1. lifts the monitor's node taints whose time is up;
2. mirrors RealTime objects, node RT attributes and Monitoring counters (every ``sync_period``, or at once
   after a watch event on RealTime objects);
3. reads nodes and pods, and records the pods in the ledger (:class:`~apps.realtime.models.RTPod`);
4. runs the engine's RT-Kube pass (``rt_kube.schedule``: sort, filter, score) over the pending pods,
   with the bound pods' reservations in the ledger, and binds each placed pod (Binding API);
5. explains every pod left pending on the pod itself (``PodScheduled`` condition and a
   ``FailedScheduling`` Event, only when the reason changes) and stores each decision
   (:class:`~apps.realtime.models.RTDecision`) with the verdict of every node on a cluster of at most
   ``rt_kube_vec.FULL_UP_TO`` nodes, else bounded: the top candidates with their scores, the count of nodes
   each filter rejected and an example of each (any node's verdict on demand: ``planning.why_not``).

A pending pod is retried every cycle, i.e. as soon as capacity frees up (a pod deleted, a taint lifted, a
node added). A failing cycle (API unreachable, database hiccup) is logged and retried with an exponential
back-off: the process never crash-loops. Monitoring objects updated in the API are ingested by the watch
thread as soon as the API reports them (the same code path as the REST endpoint).
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any

from django.db import close_old_connections, connection, transaction
from django.utils import timezone

from apps.clusters.kube import api_client_for
from apps.clusters.models import Cluster, ComputeNode
from apps.kube import gateway
from apps.kube.gateway import API_ERRORS, KubeError, node_fields
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

from . import monitoring, sync
from .kube import (
    KUBE_ERRORS,
    MONITORING_GROUP,
    MONITORING_PLURAL,
    MONITORING_VERSION,
    REALTIME_GROUP,
    REALTIME_PLURAL,
    REALTIME_VERSION,
    Kube,
    kube_for,
    parse_time,
    problem,
    requests_of,
)
from .models import MonitoringReport, RealTime, RTDecision, RTPlan, RTPod, RTPolicy

log = logging.getLogger("continuum.rt_scheduler")
STATELESS_LABEL = "rt.monitoring/stateless"
MAX_BACKOFF = 30.0
#: The ledger fields a cycle writes from the API's view of a pod (besides deleted_at, cleared, and seen).
RECORDED = ("uid", "node", "container_name", "scheduler_name", "realtime", "criticality", "stateless", "cpu",
            "memory_mib", "utilization", "owned", "phase", "bound_at")  # fmt: skip


def pod_key(pod: dict) -> str:
    return f"{pod['metadata']['namespace']}/{pod['metadata']['name']}"


def is_terminated(pod: dict) -> bool:
    return (pod.get("status") or {}).get("phase") in ("Succeeded", "Failed") or bool(
        pod["metadata"].get("deletionTimestamp")
    )


def rt_nodes(cluster: Cluster, api_nodes: list[dict]) -> list[RTNode]:
    """The engine's nodes: capacity and taints from the API, RT attributes from Continuum's node rows."""
    rows = {n.name: n for n in cluster.nodes.all()}
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
        threshold = row.rt_threshold if row and row.rt_threshold is not None else default_rt_threshold(cpu)
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


@dataclass
class CycleResult:
    bound: list[tuple[str, str]] = field(default_factory=list)
    pending: dict[str, str] = field(default_factory=dict)
    failed: dict[str, str] = field(default_factory=dict)
    lifted: int = 0
    synced: dict[str, Any] | None = None


class RTScheduler:
    """One cluster's RT scheduler (see the module docstring). ``namespace``: None = the cluster's, ``"*"`` = all."""

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
        #: While run() loops: the Events and pending explanations of a cycle are sent from this one thread
        #: (each batch with its calls overlapping) while the next cycle already decides and binds, as
        #: kube-scheduler's event broadcaster does. A cycle called on its own sends them before returning.
        self._explainer: ThreadPoolExecutor | None = None
        #: (namespace, name) -> the ledger row's fields as this process last wrote them: a row unchanged since
        #: is not written again (a cycle of 1,000 pods would upsert them all), except at each sync, when every
        #: row is written (what another writer changed meanwhile is reconciled at most sync_period late).
        self._recorded: dict[tuple[str, str], tuple] = {}

    # ---- the loop --------------------------------------------------------------------------------------------
    def run(self, stop: threading.Event | None = None, max_cycles: int | None = None) -> int:
        """Cycle until ``stop`` is set (or ``max_cycles`` ran); never raises for a failing cycle."""
        stop = stop or self.stopping
        failures = 0
        if self.use_watch:
            self._start_watches(stop)
        self._explainer = ThreadPoolExecutor(max_workers=1, thread_name_prefix="rt-explain")
        try:
            while not stop.is_set():
                wait = self.period
                try:
                    result = self.cycle()
                    failures = 0
                    if self.on_cycle:
                        self.on_cycle(result)
                    cluster = Cluster.objects.get(pk=self.cluster_id)
                    expiry = monitoring.next_taint_expiry(cluster)
                    if expiry is not None:
                        wait = min(wait, expiry + 0.01)
                except Exception as exc:  # a failing cycle must never end the process
                    failures += 1
                    self.errors += 1
                    self.last_error = problem(exc)
                    wait = min(MAX_BACKOFF, self.period * 2**failures)
                    log.warning("RT scheduler cycle failed (%s); retrying in %.1f s", self.last_error, wait)
                    close_old_connections()
                self.cycles += 1
                if max_cycles is not None and self.cycles >= max_cycles:
                    break
                self.wake.wait(wait)
                self.wake.clear()
        finally:
            stop.set()
            self.stopping.set()
            self._explainer.shutdown(wait=True)  # the explanations of the last cycle are sent
            self._explainer = None
            self._close_watches()
            deadline = time.monotonic() + 10
            for t in self.threads:
                t.join(timeout=max(0.0, deadline - time.monotonic()))
            connection.close()
        return self.cycles

    def _close_watches(self) -> None:
        """Interrupt the watch connections (a blocked read would otherwise wait for the server's timeout)."""
        self._watches.close_all()

    def cycle(self) -> CycleResult:
        cluster = Cluster.objects.get(pk=self.cluster_id)
        kube = kube_for(cluster)
        policy = RTPolicy.for_cluster(cluster)
        result = CycleResult()
        result.lifted = monitoring.lift_expired_taints(cluster)
        if self.sync_due.is_set() or time.monotonic() - self.last_sync >= self.sync_period:
            self.sync_due.clear()
            result.synced = {
                "nodes": sync.sync_node_rt(cluster, kube),
                "realtimes": sync.sync_realtimes(cluster, kube, self.namespace),
                "monitorings": sync.push_monitorings(cluster, kube),
            }
            self.last_sync = time.monotonic()
            self._recorded.clear()
        ns = sync.namespaces_of(cluster, self.namespace)
        api_nodes, pods = gather(kube.list_nodes, lambda: kube.list_pods(ns))  # two reads in one round trip's time
        pods = [p for p in pods if not is_terminated(p)]
        nodes = rt_nodes(cluster, api_nodes)
        names = [n.name for n in nodes]
        rows = cluster.realtimes.prefetch_related("wcets__node")
        if ns is not None:
            rows = rows.filter(namespace=ns)
        realtimes = {(r.namespace, r.name): r for r in rows}
        engines: dict[tuple[str, str], RTContainer | InputError] = {}
        views = [view_pod(p, realtimes, names, engines) for p in pods]
        pending = [
            v
            for v in views
            if not (v.pod.get("spec") or {}).get("nodeName")
            and (v.pod.get("spec") or {}).get("schedulerName") == RT_SCHEDULER_NAME
        ]
        if not pending:
            self._record_pods(cluster, views)
            return result
        ledger = rt_kube.Ledger.for_nodes(nodes)
        for v in views:
            node = (v.pod.get("spec") or {}).get("nodeName")
            if node and node in names and v.container is not None:
                ledger.reserve(v.container, node)
        schedulable = [v for v in pending if v.container is not None]
        # The vectorised pass (same choices as rt_kube.schedule); explanations bounded past FULL_UP_TO nodes.
        plan = rt_kube_vec.schedule(
            [v.container for v in schedulable], nodes, policy.scheduler_params(), ledger, now=time.time(), full="auto"
        )
        by_key = {v.key: v for v in pending}
        binds, stopped = self._bind_all(kube, [(by_key[d.item], d) for d in plan.decisions if d.node is not None])
        outcomes, bound_rows = [], {}
        for d in plan.decisions:
            v = by_key[d.item]
            if d.node is None:
                message = pending_message(d, len(nodes))
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
                ledger.release(d.item)
                result.failed[v.key] = message
                outcomes.append((v, d, RTDecision.Outcome.FAILED, message))
        # The ledger rows, once the binds are done: they are off the path from the watch event to the Binding.
        self._record_pods(cluster, views, bound_rows)
        for v in pending:
            if v.container is None:
                d = Decision(v.key, None)
                result.pending[v.key] = v.problem
                outcomes.append((v, d, RTDecision.Outcome.PENDING, v.problem))
        self._store(cluster, plan, outcomes)
        self._explain(kube, outcomes)
        if stopped:  # the pods bound before it are recorded; the cycle fails and is retried with back-off
            raise KubeError(stopped)
        return result

    def _bind_all(self, kube: Kube, placed: list[tuple[PodView, Decision]]) -> tuple[dict, str | None]:
        """The bind phase of every placed pod, at most ``CONTINUUM_KUBE_PUSH_CONCURRENCY`` Bindings in flight
        (the decisions are all made: binds are independent round trips). {pod key: (ok, message)} with
        ``ok=None`` for the binds not attempted after the API failed (the reason is returned)."""

        def one(item: tuple[PodView, Decision]) -> tuple[bool | None, str]:
            meta = item[0].pod["metadata"]
            return kube.bind(meta["namespace"], meta["name"], item[1].node, meta.get("uid"))

        results, stopped = run_bounded(placed, one, skipped=lambda reason: (None, reason), fatal=API_ERRORS,
                                       describe=problem)  # fmt: skip
        return {d.item: r for (_, d), r in zip(placed, results, strict=True)}, stopped

    # ---- bookkeeping ---------------------------------------------------------------------------------------
    def _record_pods(
        self, cluster: Cluster, views: list[PodView], bound: dict[tuple[str, str], tuple[str, float]] | None = None
    ) -> None:
        """Upsert the ledger rows of the pods seen (``bound``: (namespace, name) -> (node, utilisation) of the
        pods this cycle bound, bound now); pods gone from the API are marked deleted."""
        now = timezone.now()
        bound = bound or {}
        rows = []
        for v in views:
            meta, spec = v.pod["metadata"], v.pod.get("spec") or {}
            just_bound = bound.get((meta["namespace"], meta["name"]))
            node = just_bound[0] if just_bound else spec.get("nodeName") or ""
            c = v.container
            containers = spec.get("containers") or [{}]
            rows.append(
                RTPod(
                    cluster=cluster,
                    namespace=meta["namespace"],
                    name=meta["name"],
                    uid=meta.get("uid", ""),
                    node=node,
                    container_name=containers[0].get("name", ""),
                    scheduler_name=spec.get("schedulerName", ""),
                    realtime=v.realtime,
                    criticality=c.criticality if c else (v.realtime.criticality if v.realtime else NONE),
                    stateless=c.stateless if c else False,
                    cpu=c.cpu if c else 0.0,
                    memory_mib=c.memory_mib if c else 0.0,
                    utilization=(c.utilization(node) if c and node else None),
                    owned=any(o.get("controller") for o in meta.get("ownerReferences") or []),
                    phase=(v.pod.get("status") or {}).get("phase", ""),
                    bound_at=now if just_bound else (_bound_at(v.pod) if node else None),
                    deleted_at=None,
                )
            )
        seen = {(r.namespace, r.name) for r in rows}
        columns = [RTPod._meta.get_field(f).attname for f in RECORDED]
        state = {(r.namespace, r.name): tuple(getattr(r, c) for c in columns) for r in rows}
        rows = [r for r in rows if self._recorded.get((r.namespace, r.name)) != state[(r.namespace, r.name)]]
        with transaction.atomic():
            RTPod.objects.bulk_create(
                sorted(rows, key=lambda r: (r.namespace, r.name)),
                update_conflicts=True,
                unique_fields=["cluster", "namespace", "name"],
                update_fields=[*RECORDED, "deleted_at", "seen"],
            )
            live = RTPod.objects.filter(cluster=cluster, deleted_at__isnull=True)
            ns = sync.namespaces_of(cluster, self.namespace)
            if ns is not None:
                live = live.filter(namespace=ns)
            gone = [pk for pk, n, name in live.values_list("pk", "namespace", "name") if (n, name) not in seen]
            if gone:
                RTPod.objects.filter(pk__in=gone).update(deleted_at=now)
        self._recorded = {key: state[key] for key in seen}  # written (or unchanged) and committed

    def _store(self, cluster: Cluster, plan, outcomes: list) -> None:
        """Store the plan and the decisions whose outcome or reason changed since the pod's last one."""
        fresh = []
        for v, d, outcome, message in outcomes:
            uid = v.pod["metadata"].get("uid", "")
            if outcome == RTDecision.Outcome.PENDING and self.explained.get(uid) == message:
                continue
            fresh.append((v, d, outcome, message))
        if not fresh:
            return
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
        for target in (self._watch_pods, self._watch_realtimes, self._watch_monitorings):
            t = threading.Thread(target=self._follow, args=(target, stop), daemon=True, name=target.__name__)
            t.start()
            self.threads.append(t)

    def _follow(self, target, stop: threading.Event) -> None:
        """One watch thread: ``target(cluster)`` names what to follow and what to do with each event; the
        gateway's watch loop resumes it, starts over after 410 Gone and comes back after any failure (with
        exponential backoff) until ``stop``. The cluster is read again on every reconnection."""
        handlers: dict[str, Any] = {}

        def connect():
            cluster = Cluster.objects.get(pk=self.cluster_id)
            handlers["pick"], handlers["on_event"] = target(cluster)
            return api_client_for(cluster)

        try:
            gateway.follow(
                connect,
                lambda api_client: handlers["pick"](api_client),
                lambda event: handlers["on_event"](event),
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
        ns = sync.namespaces_of(cluster, self.namespace)
        pick = gateway.watch_pods(ns, field_selector=f"spec.schedulerName={RT_SCHEDULER_NAME}")
        return pick, lambda event: self.wake.set()

    def _custom(self, cluster: Cluster, group: str, version: str, plural: str):
        return gateway.watch_custom_objects(group, version, plural, sync.namespaces_of(cluster, self.namespace))

    def _watch_realtimes(self, cluster: Cluster):
        def changed(event: dict) -> None:
            obj = event.get("raw_object") or {}
            meta = obj.get("metadata") or {}
            rv = meta.get("resourceVersion")
            known = RealTime.objects.filter(
                cluster_id=self.cluster_id, namespace=meta.get("namespace"), name=meta.get("name"), resource_version=rv
            ).exists()
            if event.get("type") == "DELETED" or not known:
                self.sync_due.set()
                self.wake.set()

        return self._custom(cluster, REALTIME_GROUP, REALTIME_VERSION, REALTIME_PLURAL), changed

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

        return self._custom(cluster, MONITORING_GROUP, MONITORING_VERSION, MONITORING_PLURAL), changed

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


def _bound_at(pod: dict) -> datetime | None:
    for c in (pod.get("status") or {}).get("conditions") or []:
        if c.get("type") == "PodScheduled" and c.get("status") == "True":
            return parse_time(c.get("lastTransitionTime"))
    return parse_time(pod["metadata"].get("creationTimestamp"))
