"""deploy/: the kustomization renders the whole deployment, the server accepts it (dry run) under RBAC, and each
component's ServiceAccount may do what it needs and nothing it must not (real requests with its own token)."""

from __future__ import annotations

import subprocess

import pytest
import yaml
from kubernetes import client, config

from tests.deploy.conftest import DEPLOY, ROOT

COMPONENTS = {"continuum-web", "continuum-worker", "continuum-rt-worker", "continuum-beat", "continuum-cluster-agent",
              "continuum-rt-scheduler"}  # fmt: skip


def rendered() -> list[dict]:
    done = subprocess.run(["kubectl", "kustomize", str(DEPLOY)], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    return [d for d in yaml.safe_load_all(done.stdout) if d]


def test_kustomize_renders_every_component_with_its_own_account():
    docs = rendered()
    kinds = {(d["kind"], d["metadata"]["name"]) for d in docs}
    assert {n for k, n in kinds if k == "Deployment"} == COMPONENTS
    assert ("DaemonSet", "continuum-node-agent") in kinds
    assert {n for k, n in kinds if k == "CustomResourceDefinition"} == {"realtimes.rt.scheduling",
                                                                        "monitorings.rt.monitoring"}  # fmt: skip
    assert ("ConfigMap", "continuum-grafana-dashboard") in kinds
    accounts = {
        d["spec"]["template"]["spec"]["serviceAccountName"] for d in docs if d["kind"] in ("Deployment", "DaemonSet")
    }
    assert accounts == {"continuum-web", "continuum-worker", "continuum-beat", "continuum-cluster-agent",
                        "continuum-rt-scheduler", "continuum-node-agent"}  # fmt: skip
    for d in docs:  # nothing runs as root or keeps capabilities it does not need
        if d["kind"] in ("Deployment", "DaemonSet"):
            for c in d["spec"]["template"]["spec"]["containers"]:
                assert c["securityContext"]["allowPrivilegeEscalation"] is False
                assert c["securityContext"]["capabilities"]["drop"] == ["ALL"]
    agents = [d for d in docs if d["kind"] == "Deployment" and d["metadata"]["name"] in
              ("continuum-cluster-agent", "continuum-rt-scheduler")]  # fmt: skip
    assert all(d["spec"]["replicas"] == 2 and "--leader-elect" in " ".join(
        d["spec"]["template"]["spec"]["containers"][0]["command"]) for d in agents)  # fmt: skip


def test_the_crds_in_deploy_are_the_ones_the_code_installs():
    from apps.realtime.kube import crd_manifests

    assert [d for d in yaml.safe_load_all((DEPLOY / "crds.yaml").read_text()) if d] == crd_manifests()


def test_the_server_accepts_the_whole_deployment(rbac_api):
    done = rbac_api.kubectl("apply", "-k", str(DEPLOY), "--dry-run=server", check=False)
    assert done.returncode == 0, done.stderr
    assert "continuum-rt-scheduler" in done.stdout and "(server dry run)" in done.stdout


def api_as(rbac_api, account: str) -> client.ApiClient:
    return config.new_client_from_config_dict(yaml.safe_load(rbac_api.kubeconfig_as(rbac_api.token(account))),
                                              persist_config=False)  # fmt: skip


def forbidden(call) -> bool:
    try:
        call()
    except client.ApiException as exc:
        return exc.status == 403
    return False


POD = {"apiVersion": "v1", "kind": "Pod", "metadata": {"name": "intruder"},
       "spec": {"containers": [{"name": "c", "image": "registry.invalid/x:1"}]}}  # fmt: skip


def test_each_component_may_do_its_job_and_nothing_it_must_not(rbac_api):
    admin = config.new_client_from_config_dict(yaml.safe_load(rbac_api.api.kubeconfig()), persist_config=False)
    core = client.CoreV1Api(admin)
    core.create_node({"apiVersion": "v1", "kind": "Node", "metadata": {"name": "rbac-node"}})
    try:
        with api_as(rbac_api, "continuum-cluster-agent") as agent:
            a = client.CoreV1Api(agent)
            assert a.list_node().items is not None and a.list_namespaced_pod("continuum").items is not None
            assert a.list_namespaced_event("continuum").items is not None
            assert forbidden(lambda: a.create_namespaced_pod("continuum", POD))  # the agent only reads
            assert forbidden(lambda: a.patch_node("rbac-node", {"metadata": {"labels": {"x": "y"}}}))
            assert forbidden(lambda: a.list_namespaced_secret("continuum"))
        with api_as(rbac_api, "continuum-rt-scheduler") as sched:
            s = client.CoreV1Api(sched)
            assert s.patch_node("rbac-node", {"metadata": {"labels": {"rt.scheduling/criticality": "A"}}})
            assert forbidden(lambda: s.delete_node("rbac-node"))  # it taints and labels nodes, never deletes one
            assert forbidden(lambda: s.create_node({"apiVersion": "v1", "kind": "Node", "metadata": {"name": "n2"}}))
            assert forbidden(lambda: s.list_namespaced_secret("continuum-system"))
            assert forbidden(lambda: client.AppsV1Api(sched).list_namespaced_deployment("continuum"))
        with api_as(rbac_api, "continuum-worker") as worker:
            w = client.CoreV1Api(worker)
            assert forbidden(lambda: w.delete_node("rbac-node"))
            assert forbidden(lambda: w.list_namespaced_secret("continuum-system"))
            assert client.AppsV1Api(worker).list_namespaced_deployment("continuum").items is not None
        for account in ("continuum-web", "continuum-beat", "continuum-node-agent"):  # no Kubernetes API at all
            with api_as(rbac_api, account) as nobody:
                assert forbidden(lambda n=nobody: client.CoreV1Api(n).list_node())
                assert forbidden(lambda n=nobody: client.CoreV1Api(n).list_namespaced_pod("continuum"))
    finally:
        core.delete_node("rbac-node")
        admin.close()


@pytest.mark.parametrize("account,verb,resource,allowed", [
    ("continuum-rt-scheduler", "create", "pods/binding", True),
    ("continuum-rt-scheduler", "update", "leases.coordination.k8s.io", True),
    ("continuum-rt-scheduler", "delete", "nodes", False),
    ("continuum-cluster-agent", "create", "pods", False),
    ("continuum-cluster-agent", "create", "pods/binding", False),
    ("continuum-cluster-agent", "update", "leases.coordination.k8s.io", True),
    ("continuum-worker", "create", "pods/binding", True),
    ("continuum-worker", "delete", "customresourcedefinitions.apiextensions.k8s.io", False),
])  # fmt: skip
def test_what_each_account_may_do_in_the_workload_namespace(rbac_api, account, verb, resource, allowed):
    done = rbac_api.kubectl("auth", "can-i", verb, resource, "-n", "continuum",
                            f"--as=system:serviceaccount:continuum-system:{account}", check=False)  # fmt: skip
    assert done.stdout.strip() == ("yes" if allowed else "no"), (done.stdout, done.stderr)


def test_devcluster_and_the_test_server_authorize_with_node_and_rbac():
    for path in (ROOT / "continuum" / "devcluster.py", ROOT / "tests" / "kubeapi.py"):
        text = path.read_text()
        assert "--authorization-mode=Node,RBAC" in text and "AlwaysAllow" not in text
