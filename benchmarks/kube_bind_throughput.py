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

Printed per client: pods/s (``--pods`` / seconds until the last Binding answered), Deployments/s, and the time
from the start of its push until every pod, the bound ones and the Deployments' (made by the ReplicaSet
controller, placed by kube-scheduler), reports Running on the hollow kubelets (polled every 0.5 s); then the
gateway / plain ratio (goal: >= 1). The next client starts once the previous namespace is deleted. With
``--rounds`` > 1 the order alternates (gateway first, then plain first, ...) so drift of the loaded machine
falls on both; the ratio of the medians is printed. Hollow nodes accept at most 110 pods each.
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

import django  # noqa: E402

django.setup()

import yaml  # noqa: E402
from django.conf import settings  # noqa: E402
from kubernetes import client, config  # noqa: E402

from apps.kube import gateway  # noqa: E402
from apps.kube.pods import PodSet, pod_manifest, pod_name, push  # noqa: E402
from apps.kube.resources import pod_event  # noqa: E402
from benchmarks._bench import table  # noqa: E402
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


def run_gateway(kubeconfig: str, nodes: list[str], args, namespace: str) -> tuple[float, float]:
    """(seconds for the pods, seconds for the Deployments) through the gateway."""
    pods = PodSet(schedule=1, application=1, application_name="bench", namespace=namespace)
    work = [(a, pod_name(pods, a.task, a.frame)) for a in assignments(nodes, args.pods)]
    bodies = [deployment(namespace, i, nodes[i % len(nodes)]) for i in range(args.deployments)]
    with gateway.api_client(kubeconfig, name="bench") as api_client:
        began = time.monotonic()
        outcomes, reason = push(pods, api_client, work)
        pods_s = time.monotonic() - began
        bad = [o.message for o in outcomes if not o.ok]
        if reason or bad:
            raise RuntimeError(f"gateway push failed: {reason or bad[0]} ({len(bad)} failed)")
        began = time.monotonic()
        deployments = gateway.Deployments(api_client, namespace, HASH)
        _, current = deployments.prepare("continuum.io/group=bench")
        results, reason = deployments.apply_all([(b, current.get(b["metadata"]["name"])) for b in bodies])
        deploy_s = time.monotonic() - began
    bad = [message for ok, message in results if not ok]
    if reason or bad:
        raise RuntimeError(f"gateway Deployments failed: {reason or bad[0]} ({len(bad)} failed)")
    return pods_s, deploy_s


def run_plain(kubeconfig: str, nodes: list[str], args, namespace: str) -> tuple[float, float]:
    """The same writes with the official client and a thread pool, no retries, no checks."""
    configuration = config.new_client_from_config_dict(yaml.safe_load(kubeconfig), persist_config=False).configuration
    configuration.connection_pool_maxsize = args.threads
    api_client = client.ApiClient(configuration)
    api, apps = client.CoreV1Api(api_client), client.AppsV1Api(api_client)
    api.create_namespace(client.V1Namespace(metadata=client.V1ObjectMeta(name=namespace)))
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

    def timed(fn: Callable, items: list) -> float:
        began = time.monotonic()
        with ThreadPoolExecutor(args.threads) as pool:
            list(pool.map(fn, items))
        return time.monotonic() - began

    pods_s = timed(create_and_bind, assignments(nodes, args.pods))
    deploy_s = timed(
        create_deployment, [deployment(namespace, i, nodes[i % len(nodes)]) for i in range(args.deployments)]
    )
    api_client.close()
    return pods_s, deploy_s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nodes", type=int, default=100, help="kubemark hollow nodes (about 90 MiB each)")
    parser.add_argument("--pods", type=int, default=1000, help="pods each client pushes")
    parser.add_argument("--deployments", type=int, default=100, help="one-replica Deployments each client applies")
    parser.add_argument("--threads", type=int, default=8, help="calls in flight, both clients")
    parser.add_argument("--rounds", type=int, default=1, help="gateway/plain pairs, order alternating")
    parser.add_argument("--timeout", type=float, default=1800, help="seconds to wait for pods to run")
    args = parser.parse_args()
    if args.nodes < 1 or args.pods < 1 or args.deployments < 0 or args.threads < 1 or args.rounds < 1:
        sys.exit("--nodes, --pods, --threads and --rounds must be positive")
    if args.pods + args.deployments > args.nodes * 110:
        sys.exit(f"{args.pods + args.deployments} pods do not fit {args.nodes} hollow nodes of 110 pods each")
    settings.CONTINUUM_KUBE_PUSH_CONCURRENCY = args.threads  # the gateway's bound, and its connection pool

    doc = cluster_doc(args.nodes)
    cluster = DevCluster(tempfile.mkdtemp(prefix="bench-bind-"))
    try:
        began = time.monotonic()
        bin_dir = build_binaries(progress=progress)
        cluster.up(hollow_nodes(doc), bin_dir, timeout=max(900, 15 * args.nodes), progress=progress)
        startup = time.monotonic() - began
        kubeconfig = cluster.kubeconfig()
        nodes = [n["name"] for n in doc["nodes"]]
        print(f"== Pushing {args.pods} pods and {args.deployments} Deployments on {args.nodes} kubemark hollow nodes, "
              f"{args.threads} calls in flight, {args.rounds} round(s) ==")  # fmt: skip
        print(f"cluster up in {startup:.1f} s; {rss_line(cluster)[0]}")
        print(f"(bound pods name schedulerName {settings.CONTINUUM_SCHEDULER_NAME}: kube-scheduler places only the "
              "Deployments' pods)")  # fmt: skip
        observer = Observer(kubeconfig)
        tag = uuid.uuid4().hex[:6]
        clients = {"gateway": run_gateway, "plain": run_plain}
        measured: dict[str, list[tuple]] = {"gateway": [], "plain": []}
        rows = []
        for r in range(args.rounds):
            order = ["gateway", "plain"] if r % 2 == 0 else ["plain", "gateway"]
            for label in order:
                namespace = f"bench-{tag}-{r}-{label}"
                t0 = time.monotonic()
                pods_s, deploy_s = clients[label](kubeconfig, nodes, args, namespace)
                print(
                    f"  round {r + 1} {label}: pushed, {args.pods / pods_s:.1f} pods/s, "
                    f"{args.deployments / max(deploy_s, 1e-9):.1f} Deployments/s; waiting for Running",
                    flush=True,
                )
                bound_s, deployed_s, all_s, lost = observer.wait_running(
                    namespace, args.pods, args.deployments, t0, args.timeout
                )
                if lost:
                    print(
                        f"    {lost} bound pods evicted meanwhile (their hollow node went NotReady): not counted",
                        flush=True,
                    )
                measured[label].append((pods_s, deploy_s, all_s))
                row = [f"{r + 1}", label, args.pods / pods_s, args.deployments / deploy_s if deploy_s else 0.0,
                       pods_s, deploy_s, bound_s, deployed_s, all_s]  # fmt: skip
                rows.append(row)
                print(f"  round {r + 1} {label}: {args.pods} pods in {pods_s:.2f} s ({args.pods / pods_s:.1f} pods/s), "
                      f"{args.deployments} Deployments in {deploy_s:.2f} s; all Running {all_s:.1f} s after the "
                      "push began", flush=True)  # fmt: skip
                gone = observer.delete(namespace)
                print(f"    namespace deleted in {gone:.1f} s", flush=True)
        print()
        print(table(["round", "client", "pods/s", "Deployments/s", "pods s", "Deployments s", "bound Running s",
                     "Deployment pods Running s", "all Running s"], rows))  # fmt: skip
        med = {k: [statistics.median(x[i] for x in v) for i in range(3)] for k, v in measured.items()}
        print(f"gateway / plain, pods/s: {med['plain'][0] / med['gateway'][0]:.2f}x (median over rounds; goal >= 1)")
        if args.deployments:
            print(f"gateway / plain, Deployments/s: {med['plain'][1] / med['gateway'][1]:.2f}x")
        total_g, total_p = med["gateway"][0] + med["gateway"][1], med["plain"][0] + med["plain"][1]
        print(f"gateway / plain, all writes (pods + Deployments): {total_p / total_g:.2f}x")
        print(f"time until all Running, gateway vs plain: {med['gateway'][2]:.1f} s vs {med['plain'][2]:.1f} s")
        print(f"after the runs: {rss_line(cluster)[0]}")
        observer.api_client.close()
    finally:
        cluster.down()


if __name__ == "__main__":
    main()
