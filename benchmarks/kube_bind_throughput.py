"""Binding throughput on a live local cluster: Continuum's gateway against a plain parallel client, same run
(run on demand: ``python benchmarks/kube_bind_throughput.py [--nodes 20] [--pods 200] [--threads 8]``).

Starts a :class:`continuum.devcluster.DevCluster` (etcd, kube-apiserver, controller-manager, kube-scheduler and
``--nodes`` kubemark hollow nodes; binaries from ``scripts/build-kube.sh``, cached), then pushes ``--pods`` pods
three ways, each into a fresh namespace, round-robin over the nodes, and measures binds per second (create +
Binding, until the last bind answered) and the time until every pod reports Running (the hollow kubelets'
status, polled every 0.5 s); each run starts once the previous run's namespace is deleted:

1. ``gateway push``: :func:`apps.kube.pods.push`, what a schedule's push job runs (sequential, in rank order,
   with the gateway's retries, idempotence checks and Outcomes);
2. ``gateway parallel``: the gateway's :class:`apps.kube.pods.Pusher` (``place``: create + bind with retries) in
   a ThreadPoolExecutor of ``--threads`` workers: the same code with the plain client's parallelism;
3. ``plain parallel``: the official ``kubernetes`` client, ``create_namespaced_pod`` +
   ``create_namespaced_pod_binding`` in the same ThreadPoolExecutor, no retries, no checks.

Memory: RSS of each hollow node from /proc (about 90 MB each); use ``--nodes 100`` only on a machine with
~10 GB free. Pods are Continuum's (``schedulerName`` set, so kube-scheduler leaves them alone) with no requests.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
import uuid
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
os.environ.setdefault("DJANGO_SETTINGS_MODULE", "continuum.settings")

import django  # noqa: E402

django.setup()

from django.conf import settings  # noqa: E402
from kubernetes import client  # noqa: E402

from apps.kube import gateway  # noqa: E402
from apps.kube.pods import PodSet, Pusher, pod_manifest, pod_name, push  # noqa: E402
from benchmarks._bench import table  # noqa: E402
from continuum.devcluster import DevCluster, build_binaries, hollow_nodes, rss_mib  # noqa: E402
from continuum.engine.core.schedule import Assignment  # noqa: E402


def progress(line: str) -> None:
    print(f"  [cluster] {line}", file=sys.stderr, flush=True)


def cluster_doc(n: int) -> dict:
    return {
        "format": "continuum.cluster/v1",
        "nodes": [{"name": f"hollow-{i:03d}", "arch": "amd64", "cpu": 1, "memory_mib": 3840} for i in range(n)],
    }


def assignments(nodes: list[str], m: int) -> list[Assignment]:
    return [Assignment(task=f"t{i}", processor=nodes[i % len(nodes)], start=float(i), finish=i + 1.0) for i in range(m)]


def wait_running(api: client.CoreV1Api, namespace: str, m: int, began: float, timeout: float = 600) -> float:
    """Seconds from ``began`` until all ``m`` pods of ``namespace`` report Running."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        pods = api.list_namespaced_pod(namespace, _request_timeout=30).items
        running = sum(1 for p in pods if p.status.phase == "Running")
        if running >= m:
            return time.monotonic() - began
        time.sleep(0.5)
    raise RuntimeError(f"{namespace}: not all {m} pods Running after {timeout:.0f} s")


def wait_gone(api: client.CoreV1Api, namespace: str, timeout: float = 300) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            api.read_namespace(namespace, _request_timeout=30)
        except client.ApiException as exc:
            if exc.status == 404:
                return
            raise
        time.sleep(1)


def run_gateway_push(kubeconfig: str, nodes: list[str], m: int, namespace: str) -> float:
    pods = PodSet(schedule=1, application=1, application_name="bench", namespace=namespace)
    work = [(a, pod_name(pods, a.task, a.frame)) for a in assignments(nodes, m)]
    with gateway.api_client(kubeconfig, name="bench") as api_client:
        gateway.ensure_namespace(api_client, namespace)
        began = time.monotonic()
        outcomes, reason = push(pods, api_client, work)
        elapsed = time.monotonic() - began
    bad = [o.message for o in outcomes if not o.ok]
    if reason or bad:
        raise RuntimeError(f"gateway push failed: {reason or bad[0]} ({len(bad)} failed)")
    return elapsed


def run_gateway_parallel(kubeconfig: str, nodes: list[str], m: int, namespace: str, threads: int) -> float:
    pods = PodSet(schedule=2, application=2, application_name="bench", namespace=namespace)
    work = [(a, pod_name(pods, a.task, a.frame)) for a in assignments(nodes, m)]
    configuration = gateway.configuration_for(gateway.target(kubeconfig, name="bench"))
    configuration.connection_pool_maxsize = threads  # as many connections as workers, like the plain client
    with client.ApiClient(configuration) as api_client:
        pusher = Pusher(pods, api_client)
        pusher.ensure_namespace()
        problems = pusher.node_problems()
        began = time.monotonic()
        with ThreadPoolExecutor(threads) as pool:
            outcomes = list(pool.map(lambda w: pusher.place(w[0], w[1], None, problems), work))
        elapsed = time.monotonic() - began
    bad = [o.message for o in outcomes if not o.ok]
    if bad:
        raise RuntimeError(f"gateway parallel: {bad[0]} ({len(bad)} failed)")
    return elapsed


def run_plain(kubeconfig: str, nodes: list[str], m: int, namespace: str, threads: int) -> float:
    import yaml
    from kubernetes import config

    api_client = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False)
    api_client.configuration.connection_pool_maxsize = threads
    # new_client_from_config_dict built its pool already: a fresh client picks the size up.
    api_client = client.ApiClient(api_client.configuration)
    api = client.CoreV1Api(api_client)
    api.create_namespace(client.V1Namespace(metadata=client.V1ObjectMeta(name=namespace)))
    pods = PodSet(schedule=3, application=3, application_name="bench", namespace=namespace)

    def create_and_bind(a: Assignment) -> None:
        name = f"plain-{a.task}"
        body = pod_manifest(pods, a, name)
        body.metadata.name = name
        api.create_namespaced_pod(namespace, body)
        binding = client.V1Binding(
            metadata=client.V1ObjectMeta(name=name),
            target=client.V1ObjectReference(api_version="v1", kind="Node", name=a.processor),
        )
        response = api.create_namespaced_pod_binding(name, namespace, binding, _preload_content=False)
        response.release_conn()

    began = time.monotonic()
    with ThreadPoolExecutor(threads) as pool:
        list(pool.map(create_and_bind, assignments(nodes, m)))
    elapsed = time.monotonic() - began
    api_client.close()
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nodes", type=int, default=20)
    parser.add_argument("--pods", type=int, default=200)
    parser.add_argument("--threads", type=int, default=8, help="workers of the parallel clients")
    args = parser.parse_args()
    if args.pods * 3 > args.nodes * 110:
        sys.exit(f"{args.pods} pods x 3 runs do not fit {args.nodes} hollow nodes of 110 pods each")

    doc = cluster_doc(args.nodes)
    cluster = DevCluster(tempfile.mkdtemp(prefix="bench-bind-"))
    try:
        began = time.monotonic()
        bin_dir = build_binaries(progress=progress)
        cluster.up(hollow_nodes(doc), bin_dir, timeout=900, progress=progress)
        startup = time.monotonic() - began
        pids = cluster.processes()
        hollow = [rss_mib(pid) or 0.0 for name, pid in pids.items() if name.startswith("node/")]
        control = {name: rss_mib(pid) or 0.0 for name, pid in pids.items() if not name.startswith("node/")}
        kubeconfig = cluster.kubeconfig()
        nodes = [n["name"] for n in doc["nodes"]]
        print(f"== Binding throughput: {args.pods} pods on {args.nodes} kubemark hollow nodes, "
              f"{args.threads} threads for the parallel clients ==")  # fmt: skip
        print(f"cluster up in {startup:.1f} s; RSS per hollow node: mean {statistics.mean(hollow):.0f} MiB "
              f"(min {min(hollow):.0f}, max {max(hollow):.0f}); "
              + ", ".join(f"{k} {v:.0f} MiB" for k, v in control.items()))  # fmt: skip
        print(f"(scheduler name of the pods: {settings.CONTINUUM_SCHEDULER_NAME}; kube-scheduler leaves them alone)")

        import yaml
        from kubernetes import config

        watch_client = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False)
        watch = client.CoreV1Api(watch_client)
        rows = []
        tag = uuid.uuid4().hex[:6]
        m, threads = args.pods, args.threads
        runs = [
            ("gateway push (sequential)", lambda ns: run_gateway_push(kubeconfig, nodes, m, ns)),
            ("gateway Pusher, parallel", lambda ns: run_gateway_parallel(kubeconfig, nodes, m, ns, threads)),
            ("plain client, parallel", lambda ns: run_plain(kubeconfig, nodes, m, ns, threads)),
        ]
        results = {}
        for i, (label, run) in enumerate(runs):
            namespace = f"bench-{tag}-{i}"
            t0 = time.monotonic()
            elapsed = run(namespace)
            running = wait_running(watch, namespace, args.pods, t0)
            results[label] = elapsed
            rows.append([label, elapsed, args.pods / elapsed, running])
            print(f"  {label}: {args.pods} binds in {elapsed:.2f} s, all Running after {running:.1f} s", flush=True)
            # The next client starts on a quiet cluster: this namespace's pods deleted first.
            watch.delete_namespace(namespace)
            wait_gone(watch, namespace)
        print()
        print(table(["client", "bind s", "binds/s", "all Running s"], rows))
        plain = args.pods / results["plain client, parallel"]
        for label in ("gateway push (sequential)", "gateway Pusher, parallel"):
            ratio = (args.pods / results[label]) / plain
            print(f"{label:>28} / plain parallel: {ratio:.2f}x the binds per second")
        watch_client.close()
    finally:
        cluster.down()


if __name__ == "__main__":
    main()
