"""RT-Kube's whole loop on real nodes (issue 32, Fig. 4.21 as one real run), each stage timed:

1. Continuum's RT scheduler (a thread) binds ``lidar`` (A, stateless, a Deployment's pod) on a real node X; its
   container runs ``python3 -m continuum.agent run --realtime lidar`` over a sleeper: a SCHED_DEADLINE task in the
   pod, which reports to the live API (``rt-reports``) with no miss;
2. ``slam`` (B, a RealTime with a WCET on X only) is bound on X; its agent runs a CPU hog whose work exceeds its
   runtime: the kernel raises real overruns, the agent counts them and reports them;
3. the report over the threshold reaches the API, whose reconcile (eager Celery task) evicts ``lidar`` (the victim
   the monitor chose) and taints X;
4. the REAL ReplicaSet controller creates a new pod; the RT scheduler binds it on the other real node Y (X is
   tainted); it runs there, and its agent's reports from Y count no miss: on its new node the victim no longer
   shares X with the violator.

What "overruns stop" can mean here: SCHED_DEADLINE isolates reservations (CBS), so the violator's own runtime
overruns come from its own work and continue after the eviction (it is never the victim, thesis 3.4); what is
measured is that the evicted pod's replacement runs on Y without a miss.

The agent reaches the live server through the node's host network (``hostNetwork``: the kubelets run in the host's
network namespace, the live server listens on loopback). Its own cluster of two real nodes (root and
``KUBE_BIN_DIR/kubelet`` needed: skipped, with the reason, only when either is missing). Stage times are printed
(``-s``) and kept in TIMINGS.
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import threading
import time
import uuid
from pathlib import Path

import pytest
import yaml
from kubernetes import client, config

from continuum.devcluster import DevCluster, DevClusterError, build_binaries, hollow_nodes
from tests.kube.conftest import running_on, wait_for

pytestmark = [pytest.mark.kube, pytest.mark.root, pytest.mark.django_db(transaction=True)]

ROOT = Path(__file__).resolve().parents[2]
REAL = ("real-a", "real-b")
CLUSTER = {
    "format": "continuum.cluster/v1",
    "nodes": [{"name": n, "runtime": "real", "cpu": 1, "memory_mib": 1024} for n in REAL],
}
RT_TOLERATION = {"key": "RealTime", "operator": "Equal", "value": "RT", "effect": "NoSchedule"}
#: slam's work: a busy loop far longer than its 2 ms runtime per 10 ms period (it overruns every period).
HOG = "import time\nt = time.monotonic()\nwhile time.monotonic() - t < 900: pass\n"
#: lidar's work: a sleeper that uses microseconds of its 5 ms per 50 ms.
SLEEPER = "import time\nwhile True:\n    time.sleep(0.05)\n"
TIMINGS: dict[str, float] = {}
#: ``CONTINUUM_RT_LOOP_JSON=FILE``: the run's figures written there as JSON (benchmarks/rt_real_nodes.py --loop).
JSON_OUT = os.environ.get("CONTINUUM_RT_LOOP_JSON")


def note(what: str, seconds: float) -> None:
    TIMINGS[what] = round(seconds, 2)
    print(f"[rt-real-loop] {what}: {seconds:.2f} s (load {os.getloadavg()[0]:.1f})", file=sys.stderr, flush=True)


@pytest.fixture(scope="module")
def cluster():
    if os.geteuid() != 0:
        pytest.skip("real nodes need root (containerd, cgroups, network devices); CI runs as root")
    bin_dir = build_binaries()
    if not os.access(bin_dir / "kubelet", os.X_OK):
        pytest.skip(f"no kubelet in {bin_dir} (scripts/build-kube.sh builds it)")
    state = Path(f"/tmp/continuum-rtloop-{uuid.uuid4().hex[:8]}")  # short: containerd's socket paths (108 bytes)
    devcluster = DevCluster(state)
    began = time.monotonic()
    try:
        devcluster.up(hollow_nodes(CLUSTER), bin_dir, timeout=900, progress=lambda m: print(f"[rt-real-loop] {m}"))
    except DevClusterError as exc:
        devcluster.down()
        pytest.fail(f"the cluster with real nodes could not be started: {exc}", pytrace=False)
    note("cluster up (2 real nodes Ready)", time.monotonic() - began)
    yield devcluster
    devcluster.down()
    print(f"[rt-real-loop] timings: {TIMINGS}", file=sys.stderr)


@pytest.fixture(scope="module")
def python_image(cluster):
    """An image with Debian's python3 (buildah, FROM the base image), imported into both real nodes."""
    from apps.containers import imagebuild
    from continuum.engine.containers.image_inheritance import plan_images

    plan = plan_images({"rt": ["python3"]}, distro_image=imagebuild.BASE_IMAGE, platforms=("amd64",),
                       repository="continuum-rtloop")  # fmt: skip
    began = time.monotonic()
    built = imagebuild.build(plan, lambda p, m: None)
    ref = built["images"][-1]["reference"]
    exported = Path(f"/tmp/continuum-rtloop-image-{uuid.uuid4().hex[:6]}")
    try:
        cluster.import_image(imagebuild.export(ref, exported))
    finally:
        shutil.rmtree(exported, ignore_errors=True)  # the nodes' containerd holds the image now
    note("python3 image built and imported into both real nodes", time.monotonic() - began)
    yield f"docker.io/{ref}"
    imagebuild.remove(im["reference"] for im in built["images"])


def agent_container(name: str, image: str, server: str, token: str, cluster_id: int, code: str) -> dict:
    command = ["python3", "-m", "continuum.agent", "run", "--realtime", name, "--cluster", str(cluster_id),
               "--server", server, "--allow-http", "--flush-timeout", "120", "--http-timeout", "30", "--json",
               "--", "python3", "-c", code]  # fmt: skip
    return {
        "name": name, "image": image, "imagePullPolicy": "Never", "command": command,
        "env": [{"name": "PYTHONPATH", "value": "/opt/agent"}, {"name": "CONTINUUM_TOKEN", "value": token},
                {"name": "NODE_NAME", "valueFrom": {"fieldRef": {"fieldPath": "spec.nodeName"}}},
                {"name": "POD_NAME", "valueFrom": {"fieldRef": {"fieldPath": "metadata.name"}}}],
        "resources": {"requests": {"cpu": "100m"}},
        "securityContext": {"capabilities": {"add": ["SYS_NICE"]}},  # SCHED_DEADLINE; nothing more
        "volumeMounts": [{"name": "agent", "mountPath": "/opt/agent/continuum", "readOnly": True}],
    }  # fmt: skip


def rt_pod_spec(container: dict) -> dict:
    return {
        "schedulerName": "RT-scheduler", "tolerations": [RT_TOLERATION], "hostNetwork": True,
        "terminationGracePeriodSeconds": 1, "containers": [container],
        "volumes": [{"name": "agent", "hostPath": {"path": str(ROOT / "continuum")}}],
    }  # fmt: skip


def reports(cluster, container: str, node: str | None = None):
    from apps.realtime.models import MonitoringReport

    rows = MonitoringReport.objects.filter(cluster=cluster, container_name=container)
    return list(rows.filter(node=node) if node else rows)


def test_overruns_on_a_real_node_evict_the_victim_which_runs_elsewhere_without_misses(
    cluster, python_image, live_server, fleet_token, api, kube_admin
):
    from apps.clusters.models import Cluster
    from apps.realtime.models import RTEvent, RTPolicy
    from apps.realtime.scheduler import RTScheduler

    api_client = config.new_client_from_config_dict(yaml.safe_load(cluster.kubeconfig()), persist_config=False)
    kube, apps_api = client.CoreV1Api(api_client), client.AppsV1Api(api_client)
    ns = f"rt-{uuid.uuid4().hex[:10]}"
    doc = {"name": "real-rt", "kubeconfig": cluster.kubeconfig(), "format": "continuum.cluster/v1", "links": [],
           "nodes": [{"name": n, "arch": "amd64", "cpu": 1, "memory_mib": 1024, "rt": True, "criticality": "A"}
                     for n in REAL]}  # fmt: skip
    response = kube_admin.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 201, response.data
    response = api.patch(f"/api/v1/clusters/{response.data['id']}/", {"namespace": ns}, format="json")
    assert response.status_code == 200, response.data
    rt_cluster = Cluster.objects.get(pk=response.data["id"])
    kube.create_namespace({"metadata": {"name": ns}})
    RTPolicy.objects.create(cluster=rt_cluster, taint_duration_s=600)
    body = {"cluster": rt_cluster.pk, "name": "lidar", "criticality": "A", "period": 50, "deadline": 50,
            "stateless": True, "wcets": [{"node": n, "wcet": 5} for n in REAL]}  # fmt: skip
    response = api.post("/api/v1/realtimes/", body, format="json")
    assert response.status_code == 201, response.data
    response = api.post("/api/v1/realtimes/sync/", {"cluster": rt_cluster.pk}, format="json")
    assert response.status_code == 202, response.data
    assert api.get(f"/api/v1/jobs/{response.data['id']}/").data["state"] == "succeeded"

    sched = RTScheduler(rt_cluster.pk, period=0.2, sync_period=1.0)
    stop = threading.Event()
    thread = threading.Thread(target=sched.run, args=(stop,), daemon=True)
    thread.start()
    server, token = live_server.url, fleet_token.plaintext
    try:
        # 1. lidar: a Deployment's RT pod, bound by the RT scheduler on a real node, its agent reporting no miss.
        began = time.monotonic()
        labels = {"app": "lidar", "rt-scheduling": "lidar", "rt.monitoring/stateless": "true"}
        lidar = agent_container("lidar", python_image, server, token, rt_cluster.pk, SLEEPER)
        apps_api.create_namespaced_deployment(ns, {
            "metadata": {"name": "lidar"},
            "spec": {"replicas": 1, "selector": {"matchLabels": {"app": "lidar"}},
                     "template": {"metadata": {"labels": labels}, "spec": rt_pod_spec(lidar)}},
        })  # fmt: skip
        old, first = wait_for("lidar's pod Running on a real node", lambda: next(iter(running_on(kube, ns).items()),
                                                                                 None), timeout=300)  # fmt: skip
        note("lidar Deployment created -> its pod bound by the RT scheduler and Running", time.monotonic() - began)
        other = next(n for n in REAL if n != first)
        wait_for(f"lidar's agent reporting from {first}", lambda: reports(rt_cluster, "lidar", first), timeout=300)
        note("lidar created -> its agent's first report stored", time.monotonic() - began)
        owner = kube.read_namespaced_pod(old, ns).metadata.owner_references[0]
        assert owner.kind == "ReplicaSet"

        # 2. slam: B, runnable on `first` only, a hog under SCHED_DEADLINE (2 ms / 10 ms): real overruns.
        body = {"cluster": rt_cluster.pk, "name": "slam", "criticality": "B", "period": 10, "deadline": 10,
                "wcets": [{"node": first, "wcet": 2}]}  # fmt: skip
        response = api.post("/api/v1/realtimes/", body, format="json")
        assert response.status_code == 201, response.data
        began = time.monotonic()
        slam = agent_container("slam", python_image, server, token, rt_cluster.pk, HOG)
        spec = rt_pod_spec(slam)
        kube.create_namespaced_pod(ns, {"metadata": {"name": "slam", "labels": {"app": "slam", "rt-scheduling":
                                                                               "slam"}}, "spec": spec})  # fmt: skip
        wait_for("slam Running", lambda: running_on(kube, ns).get("slam") == first, timeout=300)
        running = time.monotonic()
        note("slam created -> bound by the RT scheduler and Running", running - began)

        # 3. The agent's report over the threshold; the reconcile evicts lidar and taints `first`.
        violation = wait_for("a report of slam over the threshold", lambda: [
            r for r in reports(rt_cluster, "slam", first) if r.violation], timeout=300)[0]  # fmt: skip
        note("slam Running -> first report over the threshold stored", time.monotonic() - running)
        assert violation.missed_period > 10 and violation.pod == "slam"
        event = wait_for("the eviction", lambda: RTEvent.objects.filter(cluster=rt_cluster, kind="eviction").first())
        evicted = time.monotonic()
        note("slam Running -> eviction decided and sent", evicted - running)
        assert event.victim == f"{ns}/{old}" and event.container == f"{ns}/slam", event.message
        assert not event.eviction_error
        assert event.node == first and event.recreated == ""  # its ReplicaSet recreates it, not Continuum
        stages = event.response.get("stages") or {}
        print(f"[rt-real-loop] reconcile stages after the report's reception (ms): {stages}", file=sys.stderr)
        print(f"[rt-real-loop] Eq. 3.19 components (ms): {event.response}", file=sys.stderr)
        taints = {(t.key, t.effect) for t in kube.read_node(first).spec.taints or []}
        assert ("rt.monitoring/violation", "NoSchedule") in taints

        # 4. The ReplicaSet's new pod, bound by the RT scheduler on the other real node, running, reporting no miss.
        new = wait_for("lidar's replacement Running", lambda: next(
            (n for n, node in running_on(kube, ns).items() if n.startswith("lidar-") and n != old), None),
            timeout=300)  # fmt: skip
        note("eviction -> the ReplicaSet's new pod bound and Running", time.monotonic() - evicted)
        pod = kube.read_namespaced_pod(new, ns)
        assert pod.spec.node_name == other and pod.spec.scheduler_name == "RT-scheduler"
        assert pod.metadata.owner_references[0].uid == owner.uid
        assert old not in {p.metadata.name for p in kube.list_namespaced_pod(ns).items}
        replaced = time.monotonic()
        # The agent reports when something is new: a 0/0 report as its command starts, then on each change.
        started = wait_for(f"the replacement's agent reporting from {other}", lambda: [
            r for r in reports(rt_cluster, "lidar", other) if r.pod == new], timeout=300)[0]  # fmt: skip
        note("replacement Running -> its agent's first report from the other node stored", time.monotonic() - replaced)
        note("eviction -> the replacement's agent reporting from the other node", time.monotonic() - evicted)
        # A window measured in the violator's own reports (each one a new overrun count, about every 0.5 s), not in
        # wall-clock time: 10 more of them, and the replacement is still running and has reported no miss.
        wait_for(
            "10 more reports of slam",
            lambda: len([r for r in reports(rt_cluster, "slam", first) if r.received_at > started.received_at]) >= 10,
            timeout=300,
        )
        later = reports(rt_cluster, "lidar", other)
        assert {r.pod for r in later} == {new}
        assert all(r.missed_total == 0 and not r.violation for r in later), [(r.missed_total, r.pod) for r in later]
        assert running_on(kube, ns).get(new) == other
        # The violator stays where it is, still overrunning its own reservation (CBS: its work, not the victim's).
        assert running_on(kube, ns)["slam"] == first
        assert max(r.missed_total for r in reports(rt_cluster, "slam", first)) > violation.missed_total
        assert sched.errors == 0, sched.last_error
        if JSON_OUT:
            slam_reports = reports(rt_cluster, "slam", first)
            Path(JSON_OUT).write_text(json.dumps({
                "stages_s": TIMINGS, "load": os.getloadavg(), "violator_node": first, "victim_new_node": other,
                "threshold_report": {"missed_period": violation.missed_period, "missed_total": violation.missed_total},
                "slam_overruns_counted": max(r.missed_total for r in slam_reports), "slam_reports": len(slam_reports),
                "replacement_reports": [{"missed_total": r.missed_total, "startup_overruns": r.startup_overruns}
                                        for r in later],
                "eviction_ms": event.response, "eviction_response_ms": event.response_ms,
            }, indent=2, default=str))  # fmt: skip
    except BaseException:
        for pod in kube.list_namespaced_pod(ns).items:  # what the agents said, for the failure's reader
            log = kube.read_namespaced_pod_log(pod.metadata.name, ns, tail_lines=20)
            print(f"[rt-real-loop] {pod.metadata.name} on {pod.spec.node_name}: {pod.status.phase}\n{log}")
        raise
    finally:
        stop.set()
        thread.join(timeout=60)
        kube.delete_namespace(ns)
        api_client.close()
