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
start them than after kube-scheduler's spreading). Pods are force-deleted between runs. Last, a cProfile of
the RT scheduler's loop over its last run, from the end of its first (idle) cycle (top 15 by own and by
cumulative time; its Binding and Event threads show as waits) and the load average.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import os
import pstats
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
PG = os.environ.get("BENCH_PG", "postgres://postgres@127.0.0.1:5432")
DB_NAME = "continuum_bench_rtlive"
NAMESPACE = "bench-rt"
PERIOD_MS, WCET_MS = 100.0, 3.0  # utilisation 0.03 per pod: 31 pods fit the 0.95 threshold of a 1-CPU node
CPU_REQUEST_M = 20  # millicores: 31 pods use 620m of a hollow node's 1 CPU
RT_TOLERATION = {"key": "RealTime", "operator": "Equal", "value": "RT", "effect": "NoSchedule"}


def progress(line: str) -> None:
    print(f"  [cluster] {line}", file=sys.stderr, flush=True)


def create_database() -> str:
    import psycopg

    with psycopg.connect(f"{PG}/postgres", autocommit=True) as conn:
        conn.execute(f"DROP DATABASE IF EXISTS {DB_NAME} WITH (FORCE)")
        conn.execute(f"CREATE DATABASE {DB_NAME}")
    return f"{PG}/{DB_NAME}"


def drop_database() -> None:
    import psycopg

    with psycopg.connect(f"{PG}/postgres", autocommit=True) as conn:
        conn.execute(f"DROP DATABASE IF EXISTS {DB_NAME} WITH (FORCE)")


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

    def wait(self, pods: int, timeout: float) -> tuple[float, float]:
        """(monotonic time the last pod was bound, the last Running)."""
        deadline = time.monotonic() + timeout
        with self.changed:
            while len(self.running) < pods or len(self.bound) < pods:
                if not self.changed.wait(timeout=max(0.0, deadline - time.monotonic())) and time.monotonic() > deadline:
                    raise RuntimeError(f"after {timeout:.0f} s: {len(self.bound)} bound, {len(self.running)} Running")
        self.stop.set()
        self.thread.join(timeout=30)
        return max(self.bound.values()), max(self.running.values())

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
    ``--serve-scheduler``), its thread profiled; started and idle (a cycle done, watches connected) before the
    first pod is created, stopped with SIGTERM after the run."""

    def __init__(self, cluster_id: int) -> None:
        self.profile_path = tempfile.mktemp(prefix="rt-scheduler-", suffix=".prof")
        self.proc = subprocess.Popen(
            [sys.executable, __file__, "--serve-scheduler", str(cluster_id), "--profile", self.profile_path],
            cwd=ROOT, stdout=subprocess.PIPE, text=True,
        )  # fmt: skip
        line = self.proc.stdout.readline() if self.proc.stdout else ""
        if not line.startswith("ready"):
            self.proc.kill()
            raise RuntimeError(f"the RT scheduler did not start: {line!r}")

    def end(self) -> tuple[pstats.Stats, str]:
        """(its profile, its last line: cycles and failures)."""
        self.proc.send_signal(signal.SIGTERM)
        out, _ = self.proc.communicate(timeout=120)
        stats = pstats.Stats(self.profile_path, stream=io.StringIO())
        os.unlink(self.profile_path)
        return stats, out.strip().splitlines()[-1] if out.strip() else ""


def serve_scheduler(cluster_id: int, profile_path: str) -> None:
    """The child: RTScheduler.run (default periods, watch on) profiled, until SIGTERM."""
    import django

    django.setup()
    from apps.realtime.scheduler import RTScheduler

    ready = threading.Event()
    profile = cProfile.Profile()

    def cycled(result) -> None:
        if not ready.is_set():  # profiled from the end of its first cycle (imports, first sync: not measured)
            profile.enable()
            ready.set()

    scheduler = RTScheduler(cluster_id, on_cycle=cycled)
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: (stop.set(), scheduler.wake.set()))

    def announce() -> None:
        if ready.wait(timeout=300):
            time.sleep(1.0)  # its watches connected
            print("ready", flush=True)

    threading.Thread(target=announce, daemon=True).start()
    scheduler.run(stop)
    profile.disable()
    profile.dump_stats(profile_path)
    print(f"{scheduler.cycles} cycles, {scheduler.errors} failed (last: {scheduler.last_error or '-'})", flush=True)


def one_run(label: str, args, kube, observer: Observer, cluster_id: int) -> tuple:
    """(seconds to all bound, seconds to all Running, seconds creating, the RT scheduler's profile and summary)
    from the first create."""
    bodies = [pod_body(i, args.realtimes, label == "rt") for i in range(args.pods)]
    run = RTRun(cluster_id) if label == "rt" else None
    profile = None
    observer.start()
    try:
        t0 = time.monotonic()
        create_s = create_pods(kube, bodies, args.threads)
        last_bound, last_running = observer.wait(args.pods, args.timeout)
    finally:
        if run is not None:
            profile = run.end()
    return last_bound - t0, last_running - t0, create_s, profile


def print_profile(stats: pstats.Stats, summary: str) -> None:
    for order in ("tottime", "cumulative"):
        out = io.StringIO()
        stats.stream = out
        stats.sort_stats(order).print_stats(15)
        lines = [line for line in out.getvalue().splitlines() if line.strip()]
        start = next((i for i, line in enumerate(lines) if "ncalls" in line), 0)
        print(f"\ncProfile of the RT scheduler's loop (its process, its last run: {summary}), top 15 by {order}:")
        print("\n".join(lines[start : start + 16]))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--nodes", type=int, default=20, help="kubemark hollow RT nodes (about 90 MiB each)")
    p.add_argument("--pods", type=int, default=300, help="pods each scheduler places per run")
    p.add_argument("--realtimes", type=int, default=10, help="RealTime objects the pods name")
    p.add_argument("--rounds", type=int, default=2, help="rt/kube pairs, order alternating")
    p.add_argument("--threads", type=int, default=8, help="pod creates in flight (both sides)")
    p.add_argument("--timeout", type=float, default=900, help="seconds to wait for all pods to run")
    p.add_argument("--keep", action="store_true", help="keep the database afterwards")
    p.add_argument("--serve-scheduler", type=int, help=argparse.SUPPRESS)  # the child process: a cluster id
    p.add_argument("--profile", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.serve_scheduler:
        serve_scheduler(args.serve_scheduler, args.profile)
        return
    per_node = int(0.95 * PERIOD_MS / WCET_MS)
    if min(args.nodes, args.pods, args.realtimes, args.rounds, args.threads) < 1:
        sys.exit("--nodes, --pods, --realtimes, --rounds and --threads must be positive")
    if args.pods > args.nodes * per_node:
        sys.exit(f"{args.pods} pods do not fit {args.nodes} RT nodes of {per_node} pods each")
    load_before = os.getloadavg()
    os.environ["DATABASE_URL"] = create_database()
    os.environ.setdefault("DJANGO_SETTINGS_MODULE", "continuum.settings")
    os.environ["LOG_LEVEL"] = "WARNING"
    env = dict(os.environ, DEBUG="0")
    subprocess.run([sys.executable, "manage.py", "migrate", "-v0"], cwd=ROOT, env=env, check=True)
    import django

    django.setup()
    from django.db import connections

    from apps.realtime.kube import kube_for
    from benchmarks._bench import table
    from continuum.devcluster import DevCluster, build_binaries, hollow_nodes

    doc = cluster_doc(args.nodes)
    dev = DevCluster(tempfile.mkdtemp(prefix="bench-rtlive-"))
    try:
        began = time.monotonic()
        dev.up(hollow_nodes(doc), build_binaries(progress=progress), timeout=max(900, 15 * args.nodes),
               progress=progress)  # fmt: skip
        print(f"== RT-Kube live: {args.pods} pods on {args.nodes} hollow RT nodes, {args.rounds} round(s); cluster "
              f"up in {time.monotonic() - began:.1f} s; load average {load_before[0]:.2f} {load_before[1]:.2f} "
              f"{load_before[2]:.2f} ==", flush=True)  # fmt: skip
        cluster = register(doc, dev.kubeconfig(), args.realtimes)
        kube = kube_for(cluster)
        observer = Observer(dev.kubeconfig())
        measured: dict[str, list[tuple[float, ...]]] = {"rt": [], "kube": []}
        rows, last_rt = [], None
        for r in range(args.rounds):
            for label in ("rt", "kube") if r % 2 == 0 else ("kube", "rt"):
                bound_s, running_s, create_s, profile = one_run(label, args, kube, observer, cluster.pk)
                last_rt = profile or last_rt
                lat = observer.latencies()
                p50, p99 = statistics.median(lat), lat[min(len(lat) - 1, round(0.99 * (len(lat) - 1)))]
                measured[label].append((bound_s, running_s, bound_s - create_s, p50, p99))
                rows.append([r + 1, label, args.pods / bound_s, bound_s, running_s, create_s, bound_s - create_s,
                             1000 * p50, 1000 * p99])  # fmt: skip
                print(f"  round {r + 1} {label}: {args.pods} pods bound in {bound_s:.2f} s "
                      f"({args.pods / bound_s:.1f} pods/s), all Running after {running_s:.2f} s (creates took "
                      f"{create_s:.2f} s); create -> bound p50 {1000 * p50:.0f} ms, p99 {1000 * p99:.0f} ms; "
                      f"load average {os.getloadavg()[0]:.2f}", flush=True)  # fmt: skip
                observer.clear()
        print()
        print(table(["round", "scheduler", "pods/s to bound", "s to all bound", "s to all Running", "s creating",
                     "s bound after last create", "create->bound p50 ms", "p99 ms"], rows))  # fmt: skip
        med = {k: [statistics.median(x[i] for x in v) for i in range(5)] for k, v in measured.items()}
        rt, ks = med["rt"], med["kube"]
        print(
            f"rt: {args.pods / rt[0]:.1f} pods/s to bound, all Running in {rt[1]:.2f} s, create -> bound p50 "
            f"{1000 * rt[3]:.0f} ms p99 {1000 * rt[4]:.0f} ms; kube-scheduler: {args.pods / ks[0]:.1f} pods/s, all "
            f"Running in {ks[1]:.2f} s, p50 {1000 * ks[3]:.0f} ms p99 {1000 * ks[4]:.0f} ms (medians over rounds)"
        )
        print(f"rt / kube-scheduler, pods/s to bound: {ks[0] / rt[0]:.2f}x (goal >= 1); time to all Running: "
              f"{ks[1] / rt[1]:.2f}x; create -> bound p50: {ks[3] / rt[3]:.2f}x, p99: {ks[4] / rt[4]:.2f}x "
              "(> 1: rt faster)")  # fmt: skip
        print(
            "(pods/s to bound includes the creates, which both sides make alike but which the apiserver serves "
            "beside each scheduler's writes; the create -> bound latencies are per pod)"
        )
        if last_rt is not None:
            print_profile(*last_rt)
        after = os.getloadavg()
        print(f"\nload average: {load_before[0]:.2f} {load_before[1]:.2f} {load_before[2]:.2f} before, "
              f"{after[0]:.2f} {after[1]:.2f} {after[2]:.2f} after (1/5/15 min; 2 cores)")  # fmt: skip
        observer.api_client.close()
    finally:
        dev.down()
        connections.close_all()
        if not args.keep:
            drop_database()


if __name__ == "__main__":
    main()
