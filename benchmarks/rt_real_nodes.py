"""RT pods on real nodes: the node agent in a pod of a real kubelet node, under SCHED_DEADLINE, with a hog.

    sudo python benchmarks/rt_real_nodes.py [--json FILE]
    sudo python benchmarks/rt_real_nodes.py --loop [--json FILE]

A cluster with two real nodes (kubelet over containerd, each its own exclusive one-CPU cpuset: its own root
domain; continuum.devcluster) and one hollow node. An image with Debian's python3 is built here (buildah, FROM
continuum/base:bookworm) and imported into both nodes. Then, timed stage by stage:

1. a pod on real-a runs ``python3 -m continuum.agent run`` (the agent from a hostPath volume, CAP_SYS_NICE added)
   over a CPU hog with 2 ms of runtime per 10 ms: the kernel admits it inside the pod's cgroup, the agent counts
   the hog's overruns (its JSON in the pod's log);
2. the pod is deleted (what the reconcile's eviction does) and a new one is created on real-b (what the
   ReplicaSet and the RT scheduler do) running the agent over a sleeper, with the default warm-up: its
   interpreter's start-up overruns are counted apart, and no miss after it.

``--loop`` measures the whole loop with the control plane closing it instead (Fig. 4.21 as one real run): it runs
tests/kube/test_rt_real_loop.py (the live API, the RT scheduler, the reconcile as an eager task, the real
ReplicaSet controller), which times each stage: agent-counted overruns of a hog on one real node -> report over the
threshold stored -> victim evicted and the node tainted -> the ReplicaSet's new pod bound by the RT scheduler on
the other real node and Running -> its agent reporting from there without a miss. The figures are printed and, with
``--json``, written.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
import uuid
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from kubernetes import client, config  # noqa: E402

from apps.containers import imagebuild  # noqa: E402
from continuum.devcluster import DevCluster, build_binaries, hollow_nodes  # noqa: E402
from continuum.engine.containers.image_inheritance import plan_images  # noqa: E402

CLUSTER = {"format": "continuum.cluster/v1", "nodes": [
    {"name": "real-a", "runtime": "real", "cpu": 1, "memory_mib": 1024},
    {"name": "real-b", "runtime": "real", "cpu": 1, "memory_mib": 1024},
    {"name": "hollow-x", "arch": "amd64", "cpu": 1},
]}  # fmt: skip
HOG = "import time\nt = time.monotonic()\nwhile time.monotonic() - t < {s}: pass\n"
SLEEP = "import os, time\nfor _ in range(40):\n    time.sleep(0.05)\nos._exit(0)\n"


def pod(name: str, node: str, image: str, code: str, warmup: tuple[str, ...] = ()) -> dict:
    agent = ["python3", "-m", "continuum.agent", "run", "--runtime-ms", "2", "--deadline-ms", "10", "--period-ms",
             "10", *warmup, "--json", "--", "python3", "-c", code]  # fmt: skip
    return {"apiVersion": "v1", "kind": "Pod", "metadata": {"name": name, "labels": {"app": "rt"}},
            "spec": {"nodeName": node, "restartPolicy": "Never", "containers": [{
                "name": "rt", "image": image, "imagePullPolicy": "Never", "command": agent,
                "env": [{"name": "PYTHONPATH", "value": "/opt/agent"}],
                "securityContext": {"capabilities": {"add": ["SYS_NICE"]}},
                "volumeMounts": [{"name": "agent", "mountPath": "/opt/agent/continuum", "readOnly": True}]}],
                "volumes": [{"name": "agent", "hostPath": {"path": str(ROOT / "continuum")}}]}}  # fmt: skip


def wait(what: str, check, timeout: float = 300):
    end = time.monotonic() + timeout
    while True:
        got = check()
        if got:
            return got
        if time.monotonic() > end:
            raise SystemExit(f"{what}: not within {timeout} s")
        time.sleep(0.1)


def run_pod(core, ns: str, body: dict, stages: dict, label: str) -> dict:
    began = time.monotonic()
    core.create_namespaced_pod(ns, body)
    name = body["metadata"]["name"]
    wait(f"{name} running", lambda: core.read_namespaced_pod(name, ns).status.phase in ("Running", "Succeeded",
                                                                                          "Failed"))  # fmt: skip
    stages[f"{label}: created -> running"] = round(time.monotonic() - began, 2)
    phase = wait(f"{name} done", lambda: core.read_namespaced_pod(name, ns).status.phase in ("Succeeded", "Failed")
                 and core.read_namespaced_pod(name, ns).status.phase)  # fmt: skip
    stages[f"{label}: created -> ended"] = round(time.monotonic() - began, 2)
    log = core.read_namespaced_pod_log(name, ns)
    lines = [ln for ln in log.splitlines() if ln.startswith("{")]
    return {"phase": phase, "result": json.loads(lines[-1]) if lines else None, "log": log[-2000:]}


def loop(json_path: Path | None) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "loop.json"
        env = {**os.environ, "CONTINUUM_RT_LOOP_JSON": str(out)}
        test = "tests/kube/test_rt_real_loop.py"
        status = subprocess.run([sys.executable, "-m", "pytest", test, "-x", "-s", "-p", "no:cacheprovider"], cwd=ROOT,
                                env=env, check=False).returncode  # fmt: skip
        if status != 0 or not out.exists():
            print(f"the loop did not complete (pytest exited {status})", file=sys.stderr)
            return 1
        text = out.read_text()
    print(text)
    if json_path:
        json_path.write_text(text)
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", type=Path)
    ap.add_argument("--loop", action="store_true", help="the whole loop with the control plane (runs its test)")
    args = ap.parse_args()
    if args.loop:
        return loop(args.json)
    stages: dict[str, float] = {}
    out: dict = {"stages": stages, "load": os.getloadavg()}
    plan = plan_images({"rt": ["python3"]}, distro_image=imagebuild.BASE_IMAGE, platforms=("amd64",),
                       repository="continuum-built")  # fmt: skip
    t = time.monotonic()
    built = imagebuild.build(plan, lambda p, m: print(f"  [{p}%] {m}", flush=True))
    ref = built["images"][-1]["reference"]
    archive = imagebuild.export(ref, Path(f"/tmp/rt-real-{uuid.uuid4().hex[:6]}"))
    stages["image built and exported"] = round(time.monotonic() - t, 1)
    state = Path(f"/tmp/continuum-rtreal-{uuid.uuid4().hex[:6]}")
    cluster = DevCluster(state)
    try:
        t = time.monotonic()
        cluster.up(hollow_nodes(CLUSTER), build_binaries(), timeout=900, progress=lambda m: print(f"[up] {m}"))
        stages["cluster up (2 real + 1 hollow, Ready)"] = round(time.monotonic() - t, 1)
        t = time.monotonic()
        cluster.import_image(archive)
        stages["image imported into both real nodes"] = round(time.monotonic() - t, 1)
        api = config.new_client_from_config_dict(yaml.safe_load(cluster.kubeconfig()), persist_config=False)
        core = client.CoreV1Api(api)
        ns = "rt-real"
        core.create_namespace({"metadata": {"name": ns}})
        image = f"docker.io/{ref}"
        hog = pod("hog-a", "real-a", image, HOG.format(s=2), ("--warmup-ms", "0"))
        out["hog_on_real_a"] = run_pod(core, ns, hog, stages, "hog pod")
        t = time.monotonic()
        core.delete_namespaced_pod("hog-a", ns, grace_period_seconds=0)
        wait("hog-a gone", lambda: not [p for p in core.list_namespaced_pod(ns).items if p.metadata.name == "hog-a"])
        stages["evicted pod gone"] = round(time.monotonic() - t, 2)
        out["sleeper_on_real_b"] = run_pod(core, ns, pod("rt-b", "real-b", image, SLEEP), stages, "recreated pod")
    finally:
        cluster.down()
        imagebuild.remove(im["reference"] for im in built["images"])
    print(json.dumps(out, indent=2, default=str))
    if args.json:
        args.json.write_text(json.dumps(out, indent=2, default=str))
    return 0


if __name__ == "__main__":
    sys.exit(main())
