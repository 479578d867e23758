"""RT-Kube on a live cluster: Continuum's RT scheduler against the real kube-scheduler placing the same pods on
the same cluster, whole path watch -> decide -> bind (issue 15; run on demand, a few minutes:
``python benchmarks/rt_kube_live.py [--nodes 20] [--pods 300] [--rounds 2]``).

Starts a :class:`continuum.devcluster.DevCluster` (etcd, kube-apiserver, controller-manager, kube-scheduler and
``--nodes`` kubemark hollow nodes, all RT nodes of criticality A: labelled and tainted ``RealTime=RT:NoSchedule``
as the RT-Kube tests register them) and registers it in Continuum in a throw-away PostgreSQL database
(``continuum_bench_rtlive`` on ``BENCH_PG``'s server, dropped afterwards): a fleet, the cluster with its
kubeconfig and namespace, its RT nodes, an RT policy and ``--realtimes`` RealTime objects (criticality A and B,
period 100 ms, a WCET on every node), mirrored into the API by the RT sync (CRDs, node taints, objects).

Each round places ``--pods`` pods twice, in alternating order (so drift of the loaded machine falls on both):

1. ``rt``: pods with ``schedulerName: RT-scheduler``, an ``rt-scheduling`` label naming a RealTime and the
   RealTime toleration, placed by :meth:`apps.realtime.scheduler.RTScheduler.run` in its own process (as
   ``manage.py rt_scheduler`` runs it: watch on, default periods), started and idle before the first pod;
2. ``kube``: the same pods with the default schedulerName, placed by the cluster's kube-scheduler.

Both sides' pods are created the same way (``--threads`` creates in flight). Measured from the first create by
an observer's watch: seconds until every pod is bound (``spec.nodeName``) and until every pod is Running
(hollow kubelets), and per pod the latency from its creation (first watch event) to its binding (p50, p99);
printed pods/s to bound (``--pods`` / seconds to all bound), the rt / kube ratios of the medians (goal >= 1)
and the time to all Running (RT-Kube packs pods onto the busiest admissible node, so fewer hollow kubelets
start them than after kube-scheduler's spreading). Pods are force-deleted between runs. Last, the profile of
the RT scheduler's last run, from the end of its first (idle) cycle, and the load average. By default
(``--scheduler-profile sample``) every thread of the process is sampled every 50 ms (benchmarks._threadprof: CPU
seconds per thread group, the functions found running; the sampler's own CPU, a few % of a core, is printed
apart); ``cprofile`` profiles the loop thread alone (top 15 by own and cumulative time; it slows that thread,
so the latencies of that run are not comparable); ``none`` measures without either.

Each rt run also prints, from the scheduler process itself, its CPU seconds per pod (all threads, from idle to the
last Binding answered; in brackets to its stop, once the pods run) and where each pod's time went inside it:
watch event received -> decided -> Binding sent -> Binding answered (p50, p99).

``--sweep`` measures how the time grows: a fresh cluster for each of ``--sweep-nodes`` (default 10,20,40), on
it ``--rounds`` rt/kube pairs for each of ``--sweep-pods`` (default 100,300,600; those that fit), no profile;
it prints every point (pods/s, p50, p99, their rt/kube ratios, the scheduler's CPU per pod) and the log-log
growth exponents of the time to all bound and of the scheduler's CPU against pods and against nodes.
The database is ``BENCH_DB`` (default ``continuum_bench_rtlive``).
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import pstats
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections import deque
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks._bench import drop_database, print_top, recreate_database  # noqa: E402

PG = os.environ.get("BENCH_PG", "postgres://postgres@127.0.0.1:5432")
DB_URL = f"{PG}/{os.environ.get('BENCH_DB', 'continuum_bench_rtlive')}"
NAMESPACE = "bench-rt"
PERIOD_MS, WCET_MS = 100.0, 3.0  # utilisation 0.03 per pod: 31 pods fit the 0.95 threshold of a 1-CPU node
CPU_REQUEST_M = 20  # millicores: 31 pods use 620m of a hollow node's 1 CPU
RT_TOLERATION = {"key": "RealTime", "operator": "Equal", "value": "RT", "effect": "NoSchedule"}


def progress(line: str) -> None:
    print(f"  [cluster] {line}", file=sys.stderr, flush=True)


def cluster_doc(n: int) -> dict:
    return {
        "format": "continuum.cluster/v1",
        "nodes": [{"name": f"rt-{i:03d}", "arch": "amd64", "cpu": 1, "memory_mib": 3840, "rt": True,
                   "criticality": "A"} for i in range(n)],
    }  # fmt: skip


def register(doc: dict, kubeconfig: str, realtimes: int):
    """The cluster in Continuum (fleet, cluster, RT nodes, policy, RealTime objects), mirrored into the API."""
    from apps.clusters.models import Cluster, ComputeNode
    from apps.realtime import sync
    from apps.realtime.models import RealTime, RealTimeWcet, RTPolicy
    from apps.tenancy.models import Fleet

    fleet = Fleet.objects.create(name="bench-rtlive", slug="bench-rtlive")
    cluster = Cluster.objects.create(fleet=fleet, name="rt-live", namespace=NAMESPACE, kubeconfig=kubeconfig)
    RTPolicy.objects.create(cluster=cluster)
    nodes = [
        ComputeNode.objects.create(cluster=cluster, name=n["name"], cpu=1, memory_mib=3840, rt=True, criticality="A")
        for n in doc["nodes"]
    ]
    for k in range(realtimes):
        rt = RealTime.objects.create(cluster=cluster, namespace=NAMESPACE, name=f"ctl-{k}", criticality="AB"[k % 2],
                                     period=PERIOD_MS, deadline=PERIOD_MS, stateless=k % 2 == 0)  # fmt: skip
        RealTimeWcet.objects.bulk_create(
            RealTimeWcet(realtime=rt, node=node, wcet=WCET_MS, position=i) for i, node in enumerate(nodes)
        )
    summary = sync.full_sync(cluster)
    errors = [e for part in summary.values() if isinstance(part, dict) for e in part.get("errors") or []]
    if errors:
        raise SystemExit(f"RT sync failed: {errors[:3]}")
    return cluster


def pod_body(i: int, realtimes: int, rt: bool) -> dict:
    spec = {
        "tolerations": [RT_TOLERATION],
        "containers": [{"name": "ctl", "image": "registry.invalid/ros:1",
                        "resources": {"requests": {"cpu": f"{CPU_REQUEST_M}m", "memory": "16Mi"}}}],
    }  # fmt: skip
    if rt:
        spec["schedulerName"] = "RT-scheduler"
    labels = {"app": "bench", "rt-scheduling": f"ctl-{i % realtimes}"}
    return {"apiVersion": "v1", "kind": "Pod", "metadata": {"name": f"p-{i:05d}", "labels": labels}, "spec": spec}


class Observer:
    """Watches the namespace's pods from its own client: when each was first seen bound and Running."""

    def __init__(self, kubeconfig: str) -> None:
        import yaml
        from kubernetes import client, config

        self.api_client = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False)
        self.api = client.CoreV1Api(self.api_client)
        self.added: dict[str, float] = {}
        self.bound: dict[str, float] = {}
        self.running: dict[str, float] = {}
        self.changed = threading.Condition()
        self.stop = threading.Event()

    def start(self) -> None:
        from apps.kube import gateway

        listing = gateway.read_json(self.api.list_namespaced_pod, NAMESPACE)
        self.added.clear()
        self.bound.clear()
        self.running.clear()
        self.stop.clear()
        self.thread = threading.Thread(target=self._watch, args=(listing["metadata"]["resourceVersion"],),
                                       daemon=True)  # fmt: skip
        self.thread.start()

    def _watch(self, version: str) -> None:
        from kubernetes import watch

        w = watch.Watch(return_type="object")  # the server's JSON: no models parsed in the scheduler's process
        while not self.stop.is_set():
            for event in w.stream(self.api.list_namespaced_pod, NAMESPACE, resource_version=version,
                                  timeout_seconds=5):  # fmt: skip
                obj = event["raw_object"]
                version = obj["metadata"]["resourceVersion"]
                name, now = obj["metadata"]["name"], time.monotonic()
                with self.changed:
                    self.added.setdefault(name, now)
                    if (obj.get("spec") or {}).get("nodeName"):
                        self.bound.setdefault(name, now)
                    if (obj.get("status") or {}).get("phase") == "Running":
                        self.running.setdefault(name, now)
                    self.changed.notify_all()
                if self.stop.is_set():
                    w.stop()

    def latencies(self) -> list[float]:
        """Seconds from each pod's creation (its first watch event) to its binding, sorted."""
        return sorted(self.bound[n] - self.added[n] for n in self.bound)

    def wait(self, pods: int, timeout: float, grace: float) -> tuple[float, float, int]:
        """(monotonic time the last pod was bound, the last Running, how many never ran). Once every pod is
        bound, the rest get ``grace`` seconds to run: a hollow node whose kubelet stopped never starts its pods,
        and the bind figures, which are what is compared, are complete by then."""
        deadline = time.monotonic() + timeout
        with self.changed:
            while len(self.running) < pods or len(self.bound) < pods:
                if len(self.bound) >= pods:
                    deadline = min(deadline, max(self.bound.values()) + grace)
                now = time.monotonic()
                if now > deadline:
                    if len(self.bound) < pods or not self.running:
                        raise RuntimeError(
                            f"after {timeout:.0f} s: {len(self.bound)} bound, {len(self.running)} Running"
                        )
                    break
                self.changed.wait(timeout=min(1.0, deadline - now))
        self.stop.set()
        self.thread.join(timeout=30)
        return max(self.bound.values()), max(self.running.values()), pods - len(self.running)

    def clear(self, timeout: float = 600) -> None:
        """Force-delete every pod of the namespace and wait until none is left."""
        from kubernetes import client

        self.api.delete_collection_namespaced_pod(NAMESPACE, grace_period_seconds=0,
                                                  body=client.V1DeleteOptions(grace_period_seconds=0))  # fmt: skip
        deadline = time.monotonic() + timeout
        while self.api.list_namespaced_pod(NAMESPACE, _request_timeout=60).items:
            if time.monotonic() > deadline:
                raise RuntimeError(f"pods of {NAMESPACE} not gone after {timeout:.0f} s")
            time.sleep(0.5)


def create_pods(kube, bodies: list[dict], threads: int) -> float:
    """Create the pods, ``threads`` in flight (the gateway's bounded pool); seconds it took."""
    from apps.kube import gateway
    from apps.kube.parallel import run_bounded

    began = time.monotonic()
    _, reason = run_bounded(bodies, lambda body: kube.create_pod(NAMESPACE, body), skipped=lambda r: None,
                            fatal=gateway.API_ERRORS, describe=gateway.problem, workers=threads)  # fmt: skip
    if reason:
        raise RuntimeError(f"creating pods failed: {reason}")
    return time.monotonic() - began


class RTRun:
    """The RT scheduler in its own process, as ``manage.py rt_scheduler`` runs it (this script with
    ``--serve-scheduler``), its loop thread profiled (unless ``profile`` is False); started and idle (a cycle
    done, its informers listed and watching) before the first pod is created, stopped with SIGTERM after the
    run."""

    def __init__(self, cluster_id: int, profile: str = "sample") -> None:
        cprofile = profile == "cprofile"
        self.profile_path = tempfile.mktemp(prefix="rt-scheduler-", suffix=".prof") if cprofile else ""
        command = [sys.executable, __file__, "--serve-scheduler", str(cluster_id)]
        if cprofile:
            command += ["--profile", self.profile_path]
        elif profile == "sample":
            command += ["--sample"]
        self.proc = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.PIPE, text=True)
        line = self.proc.stdout.readline() if self.proc.stdout else ""
        if not line.startswith("ready"):
            self.proc.kill()
            raise RuntimeError(f"the RT scheduler did not start: {line!r}")

    def end(self) -> tuple[pstats.Stats | None, dict]:
        """(its profile, its summary: cycles, failures, CPU seconds, per-pod stage timings)."""
        self.proc.send_signal(signal.SIGTERM)
        out, _ = self.proc.communicate(timeout=120)
        stats = None
        if self.profile_path:
            stats = pstats.Stats(self.profile_path, stream=io.StringIO())
            os.unlink(self.profile_path)
        last = out.strip().splitlines()[-1] if out.strip() else "{}"
        return stats, json.loads(last)


def percentiles(values: list[float]) -> tuple[float, float]:
    """(p50, p99) of the values (0, 0 when empty)."""
    if not values:
        return 0.0, 0.0
    values = sorted(values)
    return statistics.median(values), values[min(len(values) - 1, round(0.99 * (len(values) - 1)))]


class _Stamped(deque):
    """The scheduler's per-pod timings, noting the process's CPU seconds at each append (a Binding answered)."""

    cpu_at: float | None = None

    def append(self, item) -> None:
        super().append(item)
        self.cpu_at = time.process_time()


def serve_scheduler(cluster_id: int, profile_path: str | None, sample: bool = False) -> None:
    """The child: RTScheduler.run (default periods, watch on), profiled when asked, until SIGTERM; its last
    line a JSON summary (CPU seconds of the whole process from ready to the last Binding answered and to stop,
    per-pod stage timings)."""
    import django

    django.setup()
    from apps.realtime.scheduler import RTScheduler
    from benchmarks._threadprof import ThreadProfile

    ready = threading.Event()
    profile = cProfile.Profile() if profile_path else None
    sampler = ThreadProfile(interval=0.05) if sample else None
    cpu: list[float] = []

    def cycled(result) -> None:
        if not ready.is_set():  # measured from the end of its first cycle (imports, first sync: not measured)
            if profile is not None:
                profile.enable()
            ready.set()

    scheduler = RTScheduler(cluster_id, on_cycle=cycled)
    # The CPU per pod counts up to the last Binding answered (the path measured), not the writer's, the
    # explainer's and the watches' work while the hollow kubelets start the pods: each bound pod's timings are
    # appended when its Binding answered, so the process's CPU is read there.
    scheduler.timings = _Stamped(maxlen=scheduler.timings.maxlen)
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: (stop.set(), scheduler.wake.set()))

    def announce() -> None:
        if ready.wait(timeout=300):
            deadline = time.monotonic() + 60
            while not (scheduler.pods.synced and scheduler.nodes.synced and scheduler.last_sync) and (
                time.monotonic() < deadline
            ):
                time.sleep(0.05)  # its informers listed and watching, its first RT sync done (as before a cycle's)
            time.sleep(0.5)
            cpu.append(time.process_time())
            if sampler is not None:
                sampler.start()
            print("ready", flush=True)

    threading.Thread(target=announce, daemon=True).start()
    scheduler.run(stop)
    threads = sampler.finish() if sampler is not None else None
    if profile is not None:
        profile.disable()
        profile.dump_stats(profile_path)
    timings = list(scheduler.timings)
    stages = {
        name: percentiles([t[i] for t in timings])
        for i, name in enumerate(("event->decided", "decided->bind sent", "bind sent->answered"))
    }
    began = cpu[0] if cpu else 0.0
    stopped = time.process_time()
    last_bind = scheduler.timings.cpu_at if scheduler.timings.cpu_at is not None else stopped
    summary = {"cycles": scheduler.cycles, "errors": scheduler.errors, "last_error": scheduler.last_error,
               "cpu_s": last_bind - began, "cpu_to_stop_s": stopped - began, "bound": len(timings), "stages": stages,
               "writes": scheduler.ledger.writes, "write_errors": scheduler.ledger.write_errors,
               "pods": scheduler.pods.stats(), "nodes": scheduler.nodes.stats(), "api_reads": scheduler.api_reads,
               "threads": threads}  # fmt: skip
    print(json.dumps(summary), flush=True)


def one_run(label: str, pods: int, args, kube, observer: Observer, cluster_id: int, profile: bool) -> dict:
    """One side placing ``pods`` pods: seconds (from the first create) to all bound and all Running, seconds
    creating, per-pod create -> bound p50 and p99, and for ``rt`` the scheduler's profile and summary."""
    bodies = [pod_body(i, args.realtimes, label == "rt") for i in range(pods)]
    run = RTRun(cluster_id, args.scheduler_profile if profile else "none") if label == "rt" else None
    stats, summary = None, None
    observer.start()
    try:
        t0 = time.monotonic()
        create_s = create_pods(kube, bodies, args.threads)
        last_bound, last_running, never_ran = observer.wait(pods, args.timeout, args.running_grace)
    finally:
        if run is not None:
            stats, summary = run.end()
    if never_ran:
        print(
            f"  {label}: {never_ran} of {pods} pods bound but never Running within {args.running_grace:.0f} s "
            "(their hollow node's kubelet stopped?); 'all Running' is the last of the others",
            flush=True,
        )
    p50, p99 = percentiles(observer.latencies())
    out = {"bound_s": last_bound - t0, "running_s": last_running - t0, "create_s": create_s, "p50": p50,
           "p99": p99, "profile": stats, "summary": summary}  # fmt: skip
    observer.clear()
    return out


def print_profile(stats: pstats.Stats, summary: str) -> None:
    title = f"cProfile of the RT scheduler's loop thread (its process, its last run: {summary})"
    print_top(stats, title, ("tottime", "cumulative"), 15)


def print_threads(threads: dict, pods: int) -> None:
    """The sampled profile of the scheduler process's last run (benchmarks._threadprof): CPU per thread group,
    then the functions found running most often (own: at the top of the stack; inclusive: anywhere on it)."""
    total = sum(threads["cpu_by_thread"].values())
    print(f"\nRT scheduler process, its last run: CPU by thread ({total:.2f} s = {1000 * total / pods:.1f} ms/pod; "
          f"{threads['samples']} samples of every thread's state):")  # fmt: skip
    for group, seconds in threads["cpu_by_thread"].items():
        if seconds >= 0.005:
            print(f"  {group:<24} {seconds:7.3f} s  {1000 * seconds / pods:6.2f} ms/pod  "
                  f"{threads['running'].get(group, 0):5d} samples running")  # fmt: skip
    print(f"  (the sampler itself: {threads.get('self_cpu', 0):.3f} s, not counted above)")
    print("\nsampled while running, by own function (thread group, function, samples):")
    for group, fn, n in threads["own"][:20]:
        print(f"  {n:5d}  {group:<20} {fn}")
    print("\nsampled while running, by inclusive function, the top 14 of each thread group (samples):")
    for group in threads["cpu_by_thread"]:
        rows = [(fn, n) for g, fn, n in threads["inclusive"] if g == group]
        if rows:
            print(f"  {group}: " + ", ".join(f"{fn} {n}" for fn, n in rows))


def compare(pods: int, rounds: int, args, kube, observer: Observer, cluster_id: int, profile: bool, label: str):
    """``rounds`` rt/kube pairs in alternating order; per side the medians over rounds (and the runs' rows)."""
    measured: dict[str, list[dict]] = {"rt": [], "kube": []}
    for r in range(rounds):
        for side in ("rt", "kube") if r % 2 == 0 else ("kube", "rt"):
            m = one_run(side, pods, args, kube, observer, cluster_id, profile)
            measured[side].append(m)
            extra = ""
            if m["summary"]:
                sm = m["summary"]
                stages = ", ".join(f"{k} p50 {1000 * v[0]:.0f} ms p99 {1000 * v[1]:.0f} ms"
                                   for k, v in sm["stages"].items())  # fmt: skip
                to_stop = sm.get("cpu_to_stop_s", sm["cpu_s"])
                extra = (f"; scheduler process CPU to the last Binding answered {sm['cpu_s']:.2f} s = "
                         f"{1000 * sm['cpu_s'] / pods:.1f} ms/pod ({1000 * to_stop / pods:.1f} ms/pod to stop), "
                         f"{sm['cycles']} cycles ({sm.get('api_reads', 0)} listed the API: informers not in sync), "
                         f"{sm['errors']} failed; informers: pods {sm['pods']}, nodes {sm.get('nodes')}; in the "
                         f"scheduler: {stages}")  # fmt: skip
            print(f"  {label} round {r + 1} {side}: {pods} pods bound in {m['bound_s']:.2f} s "
                  f"({pods / m['bound_s']:.1f} pods/s), all Running after {m['running_s']:.2f} s (creates took "
                  f"{m['create_s']:.2f} s); create -> bound p50 {1000 * m['p50']:.0f} ms, p99 {1000 * m['p99']:.0f} "
                  f"ms; load average {os.getloadavg()[0]:.2f}{extra}", flush=True)  # fmt: skip
    keys = ("bound_s", "running_s", "create_s", "p50", "p99")
    med = {side: {k: statistics.median(m[k] for m in runs) for k in keys} for side, runs in measured.items()}
    cpu = [m["summary"]["cpu_s"] for m in measured["rt"] if m["summary"]]
    med["rt"]["cpu_s"] = statistics.median(cpu) if cpu else 0.0
    profiled = [m for m in measured["rt"] if m["profile"] is not None or (m["summary"] or {}).get("threads")]
    last = profiled[-1] if profiled else None
    return med, measured, last


def single(args, dev_kubeconfig: str, doc: dict) -> None:
    from apps.realtime.kube import kube_for
    from benchmarks._bench import table

    cluster = register(doc, dev_kubeconfig, args.realtimes)
    kube = kube_for(cluster)
    observer = Observer(dev_kubeconfig)
    med, measured, last = compare(args.pods, args.rounds, args, kube, observer, cluster.pk, True, "")
    rows = []
    for side, runs in measured.items():
        for i, m in enumerate(runs):
            rows.append([i + 1, side, args.pods / m["bound_s"], m["bound_s"], m["running_s"], m["create_s"],
                         m["bound_s"] - m["create_s"], 1000 * m["p50"], 1000 * m["p99"]])  # fmt: skip
    print()
    print(table(["round", "scheduler", "pods/s to bound", "s to all bound", "s to all Running", "s creating",
                 "s bound after last create", "create->bound p50 ms", "p99 ms"], rows))  # fmt: skip
    rt, ks = med["rt"], med["kube"]
    print(
        f"rt: {args.pods / rt['bound_s']:.1f} pods/s to bound, all Running in {rt['running_s']:.2f} s, create -> "
        f"bound p50 {1000 * rt['p50']:.0f} ms p99 {1000 * rt['p99']:.0f} ms, scheduler process CPU to the last "
        f"Binding answered {1000 * rt['cpu_s'] / args.pods:.1f} ms/pod; kube-scheduler: "
        f"{args.pods / ks['bound_s']:.1f} pods/s, all Running in {ks['running_s']:.2f} s, p50 "
        f"{1000 * ks['p50']:.0f} ms p99 {1000 * ks['p99']:.0f} ms (medians over rounds)"
    )
    print_ratios(rt, ks)
    print(
        "(pods/s to bound includes the creates, which both sides make alike but which the apiserver serves "
        "beside each scheduler's writes; the create -> bound latencies are per pod)"
    )
    if last is not None:
        sm = last["summary"]
        if last["profile"] is not None:
            print_profile(last["profile"], f"{sm['cycles']} cycles, {sm['errors']} failed")
        if sm.get("threads"):
            print_threads(sm["threads"], args.pods)
    observer.api_client.close()


def print_ratios(rt: dict, ks: dict) -> None:
    print(f"rt / kube-scheduler, pods/s to bound: {ks['bound_s'] / rt['bound_s']:.2f}x (goal >= 1); time to all "
          f"Running: {ks['running_s'] / rt['running_s']:.2f}x; create -> bound p50: {ks['p50'] / rt['p50']:.2f}x, "
          f"p99: {ks['p99'] / rt['p99']:.2f}x (> 1: rt faster)")  # fmt: skip


def sweep(args) -> None:
    """For each --sweep-nodes a fresh cluster; on it, for each --sweep-pods that fits, --rounds rt/kube pairs.
    Prints every point and the growth exponents (log-log slopes) of the time to all bound and of the rt
    scheduler's CPU, against pods at each node count and against nodes at each pod count."""
    from django.db import connections

    from apps.realtime.kube import kube_for
    from benchmarks._bench import fit_exponent, table
    from continuum.devcluster import DevCluster, build_binaries, hollow_nodes

    per_node = int(0.95 * PERIOD_MS / WCET_MS)
    points: dict[tuple[int, int], dict] = {}
    for n in args.sweep_nodes:
        doc = cluster_doc(n)
        dev = DevCluster(tempfile.mkdtemp(prefix="bench-rtlive-"))
        try:
            dev.up(hollow_nodes(doc), build_binaries(progress=progress), timeout=max(900, 15 * n), progress=progress)
            cluster = register(doc, dev.kubeconfig(), args.realtimes)
            kube = kube_for(cluster)
            observer = Observer(dev.kubeconfig())
            for pods in args.sweep_pods:
                if pods > n * per_node:
                    print(f"  ({pods} pods do not fit {n} nodes: skipped)", flush=True)
                    continue
                med, _, _ = compare(pods, args.rounds, args, kube, observer, cluster.pk, False, f"{n} nodes:")
                points[(n, pods)] = med
            observer.api_client.close()
        finally:
            dev.down()
            connections.close_all()
        _reset_database()
    rows = []
    for (n, pods), med in sorted(points.items()):
        rt, ks = med["rt"], med["kube"]
        rows.append([n, pods, pods / rt["bound_s"], pods / ks["bound_s"], ks["bound_s"] / rt["bound_s"],
                     1000 * rt["p50"], 1000 * ks["p50"], ks["p50"] / rt["p50"], 1000 * rt["p99"], 1000 * ks["p99"],
                     ks["p99"] / rt["p99"], 1000 * rt["cpu_s"] / pods])  # fmt: skip
    print()
    print(table(["nodes", "pods", "rt pods/s", "kube pods/s", "rate rt/kube", "rt p50 ms", "kube p50 ms",
                 "p50 kube/rt", "rt p99 ms", "kube p99 ms", "p99 kube/rt", "rt CPU ms/pod"], rows))  # fmt: skip
    print("(ratios > 1: rt faster; CPU: the RT scheduler process, all threads, from idle to the last Binding answered)")
    print("\ngrowth exponents k in time ~ x^k (least squares over log-log points):")

    def growth(held: str, axis: str, cells: list[tuple[int, dict]]) -> None:
        """One line per side of how the time to all bound grows along ``axis`` (the other held), and the RT
        scheduler's CPU; ``cells``: (x, medians) of the measured points."""
        if len(cells) < 2:
            return
        xs = [x for x, _ in cells]
        for side in ("rt", "kube"):
            k = fit_exponent(xs, [med[side]["bound_s"] for _, med in cells])
            print(f"  {held}, {side}: time to all bound ~ {axis}^{k:.2f}")
        k = fit_exponent(xs, [med["rt"]["cpu_s"] for _, med in cells])
        print(f"  {held}, rt scheduler CPU ~ {axis}^{k:.2f}")

    for n in args.sweep_nodes:
        growth(f"{n} nodes", "pods", [(p, points[(n, p)]) for p in args.sweep_pods if (n, p) in points])
    for pods in args.sweep_pods:
        growth(f"{pods} pods", "nodes", [(n, points[(n, pods)]) for n in args.sweep_nodes if (n, pods) in points])


def _reset_database() -> None:
    """Empty the benchmark's tables for the next cluster (the schema stays)."""
    from django.core.management import call_command

    call_command("flush", "--noinput", verbosity=0)


def ints(text: str) -> list[int]:
    try:
        values = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"comma-separated positive integers expected, got {text!r}") from None
    if not values or min(values) < 1:
        raise argparse.ArgumentTypeError(f"comma-separated positive integers expected, got {text!r}")
    return values


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--nodes", type=int, default=20, help="kubemark hollow RT nodes (about 90 MiB each)")
    p.add_argument("--pods", type=int, default=300, help="pods each scheduler places per run")
    p.add_argument("--realtimes", type=int, default=10, help="RealTime objects the pods name")
    p.add_argument("--rounds", type=int, default=2, help="rt/kube pairs, order alternating")
    p.add_argument("--threads", type=int, default=8, help="pod creates in flight (both sides)")
    p.add_argument("--timeout", type=float, default=900, help="seconds to wait for all pods to run")
    p.add_argument("--running-grace", type=float, default=60,
                   help="seconds pods get to run once all are bound (then the run goes on without them)")  # fmt: skip
    p.add_argument("--sweep", action="store_true", help="measure every --sweep-nodes x --sweep-pods point")
    p.add_argument("--sweep-nodes", type=ints, default=[10, 20, 40], help="node counts of --sweep (a cluster each)")
    p.add_argument("--sweep-pods", type=ints, default=[100, 300, 600], help="pod counts of --sweep")
    p.add_argument("--keep", action="store_true", help="keep the database afterwards")
    p.add_argument("--serve-scheduler", type=int, help=argparse.SUPPRESS)  # the child process: a cluster id
    p.add_argument("--scheduler-profile", choices=("sample", "cprofile", "none"), default="sample",
                   help="how the RT scheduler process is profiled: sampled (every thread, a few %% of a core: CPU "
                   "per thread and the functions running), cProfile of its loop thread (slows that thread), "
                   "or not")  # fmt: skip
    p.add_argument("--profile", help=argparse.SUPPRESS)
    p.add_argument("--sample", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.serve_scheduler:
        serve_scheduler(args.serve_scheduler, args.profile, args.sample)
        return
    per_node = int(0.95 * PERIOD_MS / WCET_MS)
    if min(args.nodes, args.pods, args.realtimes, args.rounds, args.threads) < 1:
        print("--nodes, --pods, --realtimes, --rounds and --threads must be positive", file=sys.stderr)
        sys.exit(2)
    if not args.sweep and args.pods > args.nodes * per_node:
        print(f"{args.pods} pods do not fit {args.nodes} RT nodes of {per_node} pods each", file=sys.stderr)
        sys.exit(2)
    load_before = os.getloadavg()
    os.environ["DATABASE_URL"] = recreate_database(DB_URL)
    os.environ.setdefault("DJANGO_SETTINGS_MODULE", "continuum.settings")
    os.environ["LOG_LEVEL"] = "WARNING"
    env = dict(os.environ, DEBUG="0")
    subprocess.run([sys.executable, "manage.py", "migrate", "-v0"], cwd=ROOT, env=env, check=True)
    import django

    django.setup()
    from django.db import connections

    from continuum.devcluster import DevCluster, build_binaries, hollow_nodes

    try:
        if args.sweep:
            print(f"== RT-Kube live sweep: nodes {args.sweep_nodes} x pods {args.sweep_pods}, {args.rounds} round(s) "
                  f"per point; load average {load_before[0]:.2f} {load_before[1]:.2f} {load_before[2]:.2f} ==",
                  flush=True)  # fmt: skip
            sweep(args)
        else:
            doc = cluster_doc(args.nodes)
            dev = DevCluster(tempfile.mkdtemp(prefix="bench-rtlive-"))
            try:
                began = time.monotonic()
                dev.up(hollow_nodes(doc), build_binaries(progress=progress), timeout=max(900, 15 * args.nodes),
                       progress=progress)  # fmt: skip
                print(f"== RT-Kube live: {args.pods} pods on {args.nodes} hollow RT nodes, {args.rounds} round(s); "
                      f"cluster up in {time.monotonic() - began:.1f} s; load average {load_before[0]:.2f} "
                      f"{load_before[1]:.2f} {load_before[2]:.2f} ==", flush=True)  # fmt: skip
                single(args, dev.kubeconfig(), doc)
            finally:
                dev.down()
        after = os.getloadavg()
        print(f"\nload average: {load_before[0]:.2f} {load_before[1]:.2f} {load_before[2]:.2f} before, "
              f"{after[0]:.2f} {after[1]:.2f} {after[2]:.2f} after (1/5/15 min; 2 cores)")  # fmt: skip
    finally:
        connections.close_all()
        if not args.keep:
            drop_database(DB_URL)


if __name__ == "__main__":
    main()
