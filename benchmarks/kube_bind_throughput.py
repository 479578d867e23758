"""Pushing at scale on a live local cluster: Continuum's gateway against a plain parallel client, same run
(issues 12 and 15; run on demand:
``python benchmarks/kube_bind_throughput.py [--nodes 100] [--pods 1000] [--deployments 100] [--threads 8]
[--rounds 1]``; a quick run: ``--nodes 10 --pods 200 --deployments 20``).

Starts a :class:`continuum.devcluster.DevCluster` (etcd, kube-apiserver, controller-manager, kube-scheduler and
``--nodes`` kubemark hollow nodes; binaries from ``scripts/build-kube.sh``, cached) and prints the RSS of each
hollow node (MiB, from /proc) and of the control plane. Then each client, in its own fresh namespace, pushes
``--pods`` pods round-robin over the nodes and ``--deployments`` one-replica Deployments pinned to nodes by
``kubernetes.io/hostname``:

1. ``gateway``: :func:`apps.kube.pods.push` (what a schedule's push job runs: namespace check, node states, the
   pods already there, then per pod create + Binding + a ``Scheduled`` Event, with the gateway's retries,
   409 checks and Outcomes, ``CONTINUUM_KUBE_PUSH_CONCURRENCY = --threads`` calls in flight) and
   :meth:`apps.kube.deployments.Deployments.apply_all` (what a placement's push runs: the Deployments already
   there, then create, or compare by hash and replace, concurrently);
2. ``plain``: the official ``kubernetes`` client with no retries and no checks doing the same writes (create pod,
   Binding, Event; create Deployment) in a ThreadPoolExecutor of ``--threads`` workers, used as its README shows
   (answers parsed into models; the Binding's answer read raw, as the client cannot parse it). The gateway reads
   the answers it does not use raw, one of the reasons it can be faster with more work per pod.

3. ``job``: the schedule push job's code, :func:`apps.scheduling.kube.push_schedule`, on a stored schedule of
   ``--pods`` assignments (its reads of the rows, the gateway's push above, the write-back of every row's
   placement in one statement), in a throw-away database (``<DATABASE_URL's name>_bind_bench``, dropped at the
   end); then its re-push (nothing to create, nothing to write back), timed as ``re-push``.

``--mode apiserver`` runs the same clients against a bare kube-apiserver (tests/kubeapi.py's, only the
``kube-apiserver`` binary from the build cache) with synthetic Ready Node objects: no kubelet runs the pods and
no controller deletes namespaces, so there is no "until Running" figure nor any Deployments (``--deployments 0``).

Both clients' timed windows hold the same work: the namespace's creation, then the pods (the gateway's window
also holds its reads before the first write: namespace, nodes, pods already there; and before the Deployments:
namespace, nodes, Deployments already there). Printed per client and round: pods/s (``--pods`` / seconds until
the last Binding answered), Deployments/s, the client process's CPU time per pod and per Deployment (ms, from
``time.process_time``: the cluster runs in other processes and the clients run one at a time, so it is the
client's own cost, and it varies far less than the wall rates on a loaded machine), the load average, and the
time from the start of its push until every pod, the bound ones and the Deployments' (made by the ReplicaSet
controller, placed by kube-scheduler), reports Running on the hollow kubelets (polled every 0.5 s). The gateway
then, once its pods run, pushes the same pods again (every pod exists and is bound: one list, no write), timed as
``re-push``. The next client starts once the previous namespace is deleted. Each client first pushes a few
pods and Deployments, unmeasured (first uses cost CPU: the client's models, TLS handshakes). Rounds alternate
the order (gateway first, then plain first, ...) so drift of the loaded machine falls on both; the summary gives
each figure's median and spread (min-max) over the rounds and the gateway / plain ratio of the medians (goal:
>= 1 for the rates, <= 1 for the CPU and the time until Running), the spread of the load average and the
hollow nodes' RSS after the runs. Hollow nodes accept at most 110 pods each.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import statistics
import sys
import tempfile
import time
import uuid
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
os.environ.setdefault("DJANGO_SETTINGS_MODULE", "continuum.settings")
# The job client's rows live in a database of their own, made (and dropped) by main(): set before Django reads it.
_BASE_DB = os.environ.get("DATABASE_URL", "postgres://postgres@127.0.0.1:5432/continuum")
BENCH_DB = _BASE_DB.rsplit("/", 1)[0] + "/" + _BASE_DB.rsplit("/", 1)[1].split("?")[0] + "_bind_bench"
os.environ["DATABASE_URL"] = BENCH_DB

import django  # noqa: E402

django.setup()

import yaml  # noqa: E402
from django.conf import settings  # noqa: E402
from kubernetes import client, config  # noqa: E402

from apps.kube import gateway  # noqa: E402
from apps.kube.pods import PodSet, pod_manifest, pod_name, push  # noqa: E402
from apps.kube.resources import pod_event  # noqa: E402
from benchmarks._bench import drop_database, recreate_database, table  # noqa: E402
from continuum.devcluster import DevCluster, build_binaries, hollow_nodes, rss_mib  # noqa: E402
from continuum.engine.core.schedule import Assignment  # noqa: E402

HASH = "continuum.io/spec-hash"


def progress(line: str) -> None:
    print(f"  [cluster] {line}", file=sys.stderr, flush=True)


def cluster_doc(n: int) -> dict:
    return {
        "format": "continuum.cluster/v1",
        "nodes": [{"name": f"hollow-{i:03d}", "arch": "amd64", "cpu": 1, "memory_mib": 3840} for i in range(n)],
    }


def assignments(nodes: list[str], m: int) -> list[Assignment]:
    return [Assignment(task=f"t{i}", processor=nodes[i % len(nodes)], start=float(i), finish=i + 1.0) for i in range(m)]


def deployment(namespace: str, i: int, node: str) -> dict:
    """A one-replica Deployment pinned to ``node`` as the container push pins them (hostname node selector)."""
    name = f"ros-c{i}"
    body = {
        "apiVersion": "apps/v1",
        "kind": "Deployment",
        "metadata": {"name": name, "namespace": namespace, "labels": {"continuum.io/group": "bench"},
                     "annotations": {}},
        "spec": {
            "replicas": 1,
            "strategy": {"type": "Recreate"},
            "selector": {"matchLabels": {"continuum.io/deployment": name}},
            "template": {
                "metadata": {"labels": {"continuum.io/deployment": name}},
                "spec": {"hostNetwork": True, "nodeSelector": {"kubernetes.io/hostname": node},
                         "containers": [{"name": "ros", "image": settings.CONTINUUM_POD_IMAGE}]},
            },
        },
    }  # fmt: skip
    body["metadata"]["annotations"][HASH] = hashlib.sha256(json.dumps(body, sort_keys=True).encode()).hexdigest()
    return body


def ready_nodes(kubeconfig: str, names: list[str]) -> None:
    """Node objects reporting Ready (a bare API server has no kubelet to make them)."""
    api_client = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False)
    with api_client:
        api = client.CoreV1Api(api_client)
        for name in names:
            labels = {"kubernetes.io/hostname": name, "kubernetes.io/arch": "amd64"}
            api.create_node({"apiVersion": "v1", "kind": "Node", "metadata": {"name": name, "labels": labels}})
            status = {"conditions": [{"type": "Ready", "status": "True", "reason": "KubeletReady", "message": "bench"}],
                      "capacity": {"cpu": "1", "memory": "3840Mi", "pods": "110"},
                      "allocatable": {"cpu": "1", "memory": "3840Mi", "pods": "110"}}  # fmt: skip
            api.patch_node_status(name, {"status": status})


def rss_line(cluster: DevCluster) -> tuple[str, list[float]]:
    pids = cluster.processes()
    hollow = [rss_mib(pid) or 0.0 for name, pid in pids.items() if name.startswith("node/")]
    control = {name: rss_mib(pid) or 0.0 for name, pid in pids.items() if not name.startswith("node/")}
    line = (
        f"RSS per hollow node: mean {statistics.mean(hollow):.1f} MiB (min {min(hollow):.1f}, max {max(hollow):.1f}; "
        f"all {len(hollow)}: {sum(hollow) / 1024:.2f} GiB); "
        + ", ".join(f"{k} {v:.0f} MiB" for k, v in control.items())
    )
    return line, hollow


class Observer:
    """A separate client that waits for pods (raw JSON: a list of 1,000 pods parses quickly)."""

    def __init__(self, kubeconfig: str) -> None:
        self.api_client = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False)
        self.api = client.CoreV1Api(self.api_client)

    def wait_running(self, namespace: str, bound: int, deployed: int, began: float, timeout: float) -> tuple:
        """(s until the bound pods run, s until the Deployments' pods run, s until all run, bound pods lost),
        from ``began``. A bound pod evicted meanwhile by the node lifecycle controller (a hollow node starved of
        CPU on a loaded machine misses its lease and turns NotReady) is not made again (no controller owns it):
        it is counted as lost, and the others are waited for."""
        deadline = time.monotonic() + timeout
        first: dict[str, float] = {}
        lost = 0
        while time.monotonic() < deadline:
            items = gateway.read_json(self.api.list_namespaced_pod, namespace, _request_timeout=60)["items"]
            live = [p for p in items if "deletionTimestamp" not in p["metadata"]]
            ours = [p for p in live if not p["metadata"].get("ownerReferences")]
            owned = [p for p in live if p["metadata"].get("ownerReferences")]
            lost = max(0, bound - len(ours))
            now = time.monotonic() - began
            if ours and all(p["status"].get("phase") == "Running" for p in ours):
                first.setdefault("bound", now)
            if sum(p["status"].get("phase") == "Running" for p in owned) >= deployed:
                first.setdefault("deployed", now)
            if "bound" in first and "deployed" in first:
                return first["bound"], first["deployed"], max(first.values()), lost
            time.sleep(0.5)
        raise RuntimeError(f"{namespace}: not all pods Running after {timeout:.0f} s ({first}, {lost} lost)")

    def delete(self, namespace: str, timeout: float = 900) -> float:
        began = time.monotonic()
        self.api.delete_namespace(namespace, _request_timeout=60)
        while time.monotonic() - began < timeout:
            try:
                self.api.read_namespace(namespace, _request_timeout=60)
            except client.ApiException as exc:
                if exc.status == 404:
                    return time.monotonic() - began
                raise
            time.sleep(1)
        print(f"  (namespace {namespace} still Terminating after {timeout:.0f} s; going on)", flush=True)
        return timeout


class Timed:
    """Wall and CPU seconds (this process's, all threads) of a ``with`` block."""

    def __enter__(self) -> Timed:
        self.wall, self.cpu = time.monotonic(), time.process_time()
        return self

    def __exit__(self, *exc) -> None:
        self.wall, self.cpu = time.monotonic() - self.wall, time.process_time() - self.cpu


def gateway_work(nodes: list[str], args, namespace: str) -> tuple[PodSet, list[tuple[Assignment, str]]]:
    pods = PodSet(schedule=1, application=1, application_name="bench", namespace=namespace)
    return pods, [(a, pod_name(pods, a.task, a.frame)) for a in assignments(nodes, args.pods)]


def run_gateway(kubeconfig: str, nodes: list[str], args, namespace: str) -> dict[str, Timed]:
    """Wall and CPU seconds of the pods and of the Deployments through the gateway."""
    pods, work = gateway_work(nodes, args, namespace)
    bodies = [deployment(namespace, i, nodes[i % len(nodes)]) for i in range(args.deployments)]
    with gateway.api_client(kubeconfig, name="bench") as api_client:
        with Timed() as pods_t:
            outcomes, reason = push(pods, api_client, work)
        check("gateway push", [o.message for o in outcomes if not o.ok], reason)
        with Timed() as deploy_t:
            deployments = gateway.Deployments(api_client, namespace, HASH)
            _, current = deployments.prepare("continuum.io/group=bench")
            results, reason = deployments.apply_all([(b, current.get(b["metadata"]["name"])) for b in bodies])
        check("gateway Deployments", [message for ok, message in results if not ok], reason)
    return {"pods": pods_t, "deployments": deploy_t}


def repush_gateway(kubeconfig: str, nodes: list[str], args, namespace: str) -> Timed:
    """The gateway's push of the same pods again: each is listed, found bound to its node and left alone."""
    pods, work = gateway_work(nodes, args, namespace)
    with gateway.api_client(kubeconfig, name="bench") as api_client, Timed() as again:
        outcomes, reason = push(pods, api_client, work)
    bad = [o.message for o in outcomes if not o.ok]
    if reason or bad:  # a hollow node starved of CPU may be NotReady meanwhile: reported, not fatal
        print(f"    re-push: {len(bad)} placements failed: {reason or bad[0]}", flush=True)
    return again


class JobRows:
    """The database side of the ``job`` client: a fleet, a cluster row pointing at the test cluster, and a
    fresh stored schedule of ``--pods`` assignments per push (the namespace is the cluster's)."""

    def __init__(self, kubeconfig: str) -> None:
        from django.core.management import call_command

        from apps.clusters.models import Cluster
        from apps.tenancy.models import Fleet

        call_command("migrate", verbosity=0)
        self.fleet, _ = Fleet.objects.get_or_create(slug="bind-bench", defaults={"name": "bind-bench"})
        self.cluster = Cluster.objects.create(fleet=self.fleet, name="bench", kubeconfig=kubeconfig)
        self.count = 0

    def schedule(self, nodes: list[str], m: int, namespace: str):
        from django.db import transaction

        from apps.scheduling.models import Schedule
        from apps.workloads.models import Application
        from continuum.engine.core.platform import Platform, Processor
        from continuum.engine.core.schedule import Schedule as EngineSchedule

        self.count += 1
        self.cluster.namespace = namespace
        self.cluster.save(update_fields=["namespace"])
        app = Application.objects.create(fleet=self.fleet, name=f"bench-{self.count}", dag={})
        platform = Platform([Processor(n) for n in nodes])
        with transaction.atomic():
            row = Schedule.store(EngineSchedule("heft", assignments(nodes, m)), application=app, platform=platform)
        row.cluster = self.cluster
        row.save(update_fields=["cluster"])
        return row


JOB: dict[str, JobRows] = {}


def run_job(kubeconfig: str, nodes: list[str], args, namespace: str) -> dict[str, Timed]:
    """The push job's code on a stored schedule (rows read, pods pushed, placements written back)."""
    from apps.scheduling.kube import push_schedule
    from apps.scheduling.models import Schedule

    if "rows" not in JOB:
        JOB["rows"] = JobRows(kubeconfig)
    rows = JOB["rows"]
    stored = rows.schedule(nodes, args.pods, namespace)
    schedule = Schedule.objects.select_related("cluster", "application").get(pk=stored.pk)
    with Timed() as pods_t:
        summary = push_schedule(schedule)
    check("job push", [] if summary["failed"] == 0 else [f"{summary['failed']} failed"], None)
    JOB["last"] = schedule  # type: ignore[assignment]
    return {"pods": pods_t, "deployments": _zero()}


def _zero() -> Timed:
    """No Deployments: the job pushes pods only."""
    t = Timed()
    t.wall = t.cpu = 1e-9
    return t


def repush_job(kubeconfig: str, nodes: list[str], args, namespace: str) -> Timed:
    """The job again on the same schedule: every pod exists and is bound, no row changes."""
    from apps.scheduling.kube import push_schedule
    from apps.scheduling.models import Schedule

    last = JOB["last"]
    schedule = Schedule.objects.select_related("cluster", "application").get(pk=last.pk)  # type: ignore[attr-defined]
    with Timed() as again:
        push_schedule(schedule)
    return again


def check(what: str, bad: list[str], reason: str | None) -> None:
    if reason or bad:
        raise RuntimeError(f"{what} failed: {reason or bad[0]} ({len(bad)} failed)")


def run_plain(kubeconfig: str, nodes: list[str], args, namespace: str) -> dict[str, Timed]:
    """The same writes with the official client and a thread pool, no retries, no checks."""
    configuration = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False).configuration
    configuration.connection_pool_maxsize = args.threads
    api_client = client.ApiClient(configuration)
    api, apps = client.CoreV1Api(api_client), client.AppsV1Api(api_client)
    pods = PodSet(schedule=2, application=2, application_name="bench", namespace=namespace)

    def create_and_bind(a: Assignment) -> None:
        name = pod_name(pods, a.task, a.frame)
        api.create_namespaced_pod(namespace, pod_manifest(pods, a, name))
        binding = client.V1Binding(
            metadata=client.V1ObjectMeta(name=name),
            target=client.V1ObjectReference(api_version="v1", kind="Node", name=a.processor),
        )
        api.create_namespaced_pod_binding(name, namespace, binding, _preload_content=False).release_conn()
        event = pod_event(namespace, name, "Scheduled", f"Successfully assigned {namespace}/{name} to {a.processor}",
                          settings.CONTINUUM_SCHEDULER_NAME)  # fmt: skip
        api.create_namespaced_event(namespace, event)

    def create_deployment(body: dict) -> None:
        apps.create_namespaced_deployment(namespace, body)

    def timed(fn: Callable, items: list, first: Callable[[], object] = lambda: None) -> Timed:
        with Timed() as t:
            first()
            with ThreadPoolExecutor(args.threads) as pool:
                list(pool.map(fn, items))
        return t

    # The namespace is made in the timed window, as the gateway's push makes it in its own.
    pods_t = timed(
        create_and_bind,
        assignments(nodes, args.pods),
        lambda: api.create_namespace(client.V1Namespace(metadata=client.V1ObjectMeta(name=namespace))),
    )
    deploy_t = timed(
        create_deployment, [deployment(namespace, i, nodes[i % len(nodes)]) for i in range(args.deployments)]
    )
    api_client.close()
    return {"pods": pods_t, "deployments": deploy_t}


def spread(values: list[float], unit: str, digits: int = 1) -> str:
    """``median [min-max] unit`` of a figure over the rounds."""
    return f"{statistics.median(values):.{digits}f} [{min(values):.{digits}f}-{max(values):.{digits}f}] {unit}".rstrip()


def load() -> str:
    return "load average " + " ".join(f"{x:.1f}" for x in os.getloadavg())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nodes", type=int, default=100, help="kubemark hollow nodes (about 90 MiB each)")
    parser.add_argument("--pods", type=int, default=1000, help="pods each client pushes")
    parser.add_argument("--deployments", type=int, default=100, help="one-replica Deployments each client applies")
    parser.add_argument("--threads", type=int, default=8, help="calls in flight, both clients")
    parser.add_argument("--rounds", type=int, default=1, help="gateway/plain pairs, order alternating")
    parser.add_argument("--timeout", type=float, default=1800, help="seconds to wait for pods to run")
    parser.add_argument(
        "--mode",
        choices=("live", "apiserver"),
        default="live",
        help="live: a DevCluster with hollow nodes; apiserver: a bare kube-apiserver, Node objects",
    )
    args = parser.parse_args()
    if args.nodes < 1 or args.pods < 1 or args.deployments < 0 or args.threads < 1 or args.rounds < 1:
        sys.exit("--nodes, --pods, --threads and --rounds must be positive")
    if args.mode == "apiserver":
        args.deployments = 0  # no controller makes their pods
    if args.mode == "live" and args.pods + args.deployments > args.nodes * 110:
        sys.exit(f"{args.pods + args.deployments} pods do not fit {args.nodes} hollow nodes of 110 pods each")
    settings.CONTINUUM_KUBE_PUSH_CONCURRENCY = args.threads  # the gateway's bound, and its connection pool

    doc = cluster_doc(args.nodes)
    recreate_database(BENCH_DB)
    cluster: DevCluster | None = None
    server = None
    try:
        began = time.monotonic()
        if args.mode == "live":
            cluster = DevCluster(tempfile.mkdtemp(prefix="bench-bind-"))
            bin_dir = build_binaries(progress=progress)
            cluster.up(hollow_nodes(doc), bin_dir, timeout=max(900, 15 * args.nodes), progress=progress)
            kubeconfig = cluster.kubeconfig()
        else:
            from tests.kubeapi import KubeAPIServer, build_kube_apiserver

            server = KubeAPIServer(build_kube_apiserver()).start()
            kubeconfig = server.kubeconfig()
            ready_nodes(kubeconfig, [n["name"] for n in doc["nodes"]])
        startup = time.monotonic() - began
        nodes = [n["name"] for n in doc["nodes"]]
        where = "kubemark hollow nodes" if cluster else "synthetic Ready nodes of a bare kube-apiserver"
        print(f"== Pushing {args.pods} pods and {args.deployments} Deployments on {args.nodes} {where}, "
              f"{args.threads} calls in flight, {args.rounds} round(s) ==")  # fmt: skip
        print(f"cluster up in {startup:.1f} s; {rss_line(cluster)[0] if cluster else ''}; {load()}")
        print(f"(bound pods name schedulerName {settings.CONTINUUM_SCHEDULER_NAME}: kube-scheduler places only the "
              "Deployments' pods)")  # fmt: skip
        observer = Observer(kubeconfig)
        tag = uuid.uuid4().hex[:6]
        clients = {"gateway": run_gateway, "plain": run_plain, "job": run_job}
        repush = {"gateway": repush_gateway, "job": repush_job}
        measured: dict[str, list[dict[str, float]]] = {"gateway": [], "plain": [], "job": []}
        rows = []
        n_pods, n_dep = args.pods, max(args.deployments, 1)
        # Unmeasured warm-up of each client: the first use of a model, an API class or a connection costs CPU
        # (pydantic validators, TLS handshakes) that would otherwise fall on whichever client goes first.
        warm = argparse.Namespace(**{**vars(args), "pods": min(args.pods, 2 * args.threads),
                                     "deployments": min(args.deployments, 4)})  # fmt: skip
        for label, run in clients.items():
            run(kubeconfig, nodes, warm, f"bench-{tag}-warm-{label}")
            if label in repush:
                repush[label](kubeconfig, nodes, warm, f"bench-{tag}-warm-{label}")
            if cluster:
                observer.delete(f"bench-{tag}-warm-{label}")
        print(f"warmed up both clients ({warm.pods} pods, {warm.deployments} Deployments each); {load()}", flush=True)
        for r in range(args.rounds):
            order = ["gateway", "job", "plain"] if r % 2 == 0 else ["plain", "job", "gateway"]
            for label in order:
                namespace = f"bench-{tag}-{r}-{label}"
                t0 = time.monotonic()
                timed = clients[label](kubeconfig, nodes, args, namespace)
                pods_t, deploy_t = timed["pods"], timed["deployments"]
                figures = {
                    "pods/s": n_pods / pods_t.wall,
                    "Deployments/s": args.deployments / deploy_t.wall if args.deployments else 0.0,
                    "CPU ms/pod": 1000 * pods_t.cpu / n_pods,
                    "CPU ms/Deployment": 1000 * deploy_t.cpu / n_dep,
                }
                measured[label].append(figures)
                load1 = os.getloadavg()[0]
                f = figures
                print(
                    f"  round {r + 1} {label}: {f['pods/s']:.1f} pods/s ({f['CPU ms/pod']:.2f} ms CPU/pod), "
                    f"{f['Deployments/s']:.1f} Deployments/s ({f['CPU ms/Deployment']:.2f} ms CPU/Deployment); "
                    f"load {load1:.1f}; waiting for Running",
                    flush=True,
                )
                if cluster:
                    bound_s, deployed_s, all_s, lost = observer.wait_running(
                        namespace, args.pods, args.deployments if label != "job" else 0, t0, args.timeout
                    )
                else:  # no kubelet: nothing runs
                    bound_s = deployed_s = all_s = float("nan")
                    lost = 0
                again = None
                if label in repush:  # after the wait: it must not delay the pods' start
                    again = repush[label](kubeconfig, nodes, args, namespace)
                    figures["re-push s"] = again.wall
                    figures["re-push CPU ms/pod"] = 1000 * again.cpu / n_pods
                    cpu_ms = figures["re-push CPU ms/pod"]
                    print(f"    re-push: {again.wall:.2f} s ({cpu_ms:.3f} ms CPU/pod)", flush=True)
                if lost:
                    print(
                        f"    {lost} bound pods evicted meanwhile (their hollow node went NotReady): not counted",
                        flush=True,
                    )
                figures["all Running s"] = all_s
                figures["load 1 min"] = load1
                rows.append([f"{r + 1}", label, figures["pods/s"], figures["Deployments/s"], figures["CPU ms/pod"],
                             figures["CPU ms/Deployment"], pods_t.wall, deploy_t.wall,
                             again.wall if again else "-", bound_s, deployed_s, all_s, load1])  # fmt: skip
                if cluster:
                    gone = observer.delete(namespace)
                    print(f"    namespace deleted in {gone:.1f} s", flush=True)
        print()
        print(table(["round", "client", "pods/s", "Deployments/s", "CPU ms/pod", "CPU ms/Deployment", "pods s",
                     "Deployments s", "re-push s", "bound Running s", "Deployment pods Running s", "all Running s",
                     "load 1 min"], rows))  # fmt: skip
        print()
        print(f"median [min-max] over {args.rounds} round(s); {load()}")
        units = {"pods/s": "pods/s", "Deployments/s": "Deployments/s", "CPU ms/pod": "ms CPU/pod",
                 "CPU ms/Deployment": "ms CPU/Deployment", "all Running s": "s until all Running"}  # fmt: skip
        med = {}
        for key, unit in units.items():
            if key in ("Deployments/s", "CPU ms/Deployment") and not args.deployments:
                continue
            if key == "all Running s" and not cluster:
                continue
            g = [f[key] for f in measured["gateway"]]
            p = [f[key] for f in measured["plain"]]
            med[key] = statistics.median(g) / statistics.median(p)
            digits = 2 if "CPU" in key else 1
            print(f"  {key:18s} gateway {spread(g, unit, digits)}; plain {spread(p, unit, digits)}; "
                  f"gateway / plain {med[key]:.2f}x")  # fmt: skip
        for label in repush:
            runs = measured[label]
            print(f"  {label} re-push of the {args.pods} pods (all exist): "
                  f"{spread([f['re-push s'] for f in runs], 's', 2)}, "
                  f"{spread([f['re-push CPU ms/pod'] for f in runs], 'ms CPU/pod', 3)}")  # fmt: skip
        j = [f["pods/s"] for f in measured["job"]]
        jc = [f["CPU ms/pod"] for f in measured["job"]]
        p = [f["pods/s"] for f in measured["plain"]]
        print(f"  {'pods/s':18s} job {spread(j, 'pods/s')} ({spread(jc, 'ms CPU/pod', 2)}); job / plain "
              f"{statistics.median(j) / statistics.median(p):.2f}x (goal >= 1); re-push goal < 1 s")  # fmt: skip
        loads = [f["load 1 min"] for label in measured for f in measured[label]]
        print(f"  load average (1 min) at the end of each client's push: {spread(loads, '')}")
        print(f"gateway / plain, pods/s: {med['pods/s']:.2f}x (ratio of the medians; goal >= 1)")
        if args.deployments:
            print(f"gateway / plain, Deployments/s: {med['Deployments/s']:.2f}x (goal >= 1)")
        print(f"gateway / plain, CPU per pod: {med['CPU ms/pod']:.2f}x (goal <= 1)")
        if args.deployments:
            print(f"gateway / plain, CPU per Deployment: {med['CPU ms/Deployment']:.2f}x (goal <= 1)")
        if cluster:
            print(f"gateway / plain, time until all Running: {med['all Running s']:.2f}x (goal <= 1)")
            print(f"after the runs: {rss_line(cluster)[0]}; {load()}")
        observer.api_client.close()
    finally:
        from django.db import connections

        connections.close_all()
        if cluster:
            cluster.down()
        if server:
            server.stop()
        drop_database(BENCH_DB)


if __name__ == "__main__":
    main()
