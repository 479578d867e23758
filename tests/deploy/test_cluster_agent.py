"""The cluster agent as deployed: ``manage.py cluster_agent --leader-elect`` with the agent's own ServiceAccount
under RBAC (it may only read), its Lease in the cluster's namespace. A node whose kubelet stops posting goes
Unknown: its row turns not ready (the alarm); a schedule's pod shows its state with no command started by hand;
a pod elsewhere carrying the schedule's labels changes nothing; /metrics counts what it handled."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest
import yaml
from django.contrib.auth.models import Permission
from kubernetes import client, config
from rest_framework.test import APIClient

from apps.clusters.models import Cluster, ComputeNode
from apps.kube.gateway import PREFIX
from tests.deploy.conftest import ROOT
from tests.deploy.test_leader import NS, wait_for
from tests.kubeapi import free_port
from tests.scrape import scrape_until, total
from tests.services.conftest import database_url

pytestmark = [pytest.mark.kube, pytest.mark.django_db(transaction=True)]


def condition(status):
    now = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    return {"type": "Ready", "status": status, "reason": "Kubelet", "lastHeartbeatTime": now, "lastTransitionTime": now}


def test_the_agent_keeps_node_status_and_live_pod_state_with_its_own_account(
    rbac_api, fleet, schedule, django_user_model, cluster_doc, tmp_path
):
    admin = config.new_client_from_config_dict(yaml.safe_load(rbac_api.api.kubeconfig()), persist_config=False)
    core = client.CoreV1Api(admin)
    user = django_user_model.objects.create_user("kube-admin")
    fleet.members.add(user)
    user.user_permissions.add(Permission.objects.get(codename="change_cluster_credentials"))
    operator = APIClient()
    operator.force_login(user)
    doc = {"name": "agent", "kubeconfig": rbac_api.api.kubeconfig(), "namespace": NS, **cluster_doc}
    response = operator.post("/api/v1/clusters/import/", doc, format="json")
    assert response.status_code == 201, response.data
    cluster = Cluster.objects.get(pk=response.data["id"])
    names = [n["name"] for n in cluster_doc["nodes"]]
    for name in names:
        core.create_node({"apiVersion": "v1", "kind": "Node", "metadata": {"name": name}})
        core.patch_node_status(name, {"status": {"conditions": [condition("True")]}})
    schedule.cluster = cluster
    schedule.save(update_fields=["cluster"])
    assignment = schedule.assignments.first()
    assignment.pod_name = "task-pod"
    assignment.save(update_fields=["pod_name"])
    labels = {f"{PREFIX}/schedule": str(schedule.pk), f"{PREFIX}/application": str(schedule.application_id)}
    spec = {"containers": [{"name": "c", "image": "registry.invalid/t:1"}], "nodeName": names[0]}
    token = rbac_api.token_file("continuum-cluster-agent")
    port = free_port()
    env = dict(os.environ, DATABASE_URL=database_url(), CONTINUUM_JOBS_EAGER="1", CONTINUUM_KUBE_TOKEN_FILE=str(token),
               CONTINUUM_KUBE_TOKEN_SERVER=rbac_api.server)  # fmt: skip
    log = tmp_path / "agent.log"
    proc = subprocess.Popen([sys.executable, "manage.py", "cluster_agent", "--cluster", str(cluster.pk),
                             "--leader-elect", "--metrics-port", str(port)], cwd=ROOT, env=env,
                            stdout=log.open("w"), stderr=subprocess.STDOUT, start_new_session=True)  # fmt: skip
    try:
        wait_for("the agent's Lease", lambda: _holder(admin))
        # A node whose kubelet stopped posting: Unknown, and Unknown is not ready.
        core.patch_node_status(names[1], {"status": {"conditions": [condition("Unknown")]}})
        wait_for("node1 Unknown", lambda: ComputeNode.objects.get(cluster=cluster, name=names[1]).status == "Unknown")
        assert cluster.nodes.exclude(status=ComputeNode.Status.READY).count() == 1
        # The schedule's pod, in the cluster's namespace: its state shows with nothing started by hand ...
        core.create_namespace({"metadata": {"name": "elsewhere"}})
        core.create_namespaced_pod(NS, {"metadata": {"name": "task-pod", "labels": labels}, "spec": spec})
        core.patch_namespaced_pod_status("task-pod", NS, {"status": {"phase": "Running"}})
        assignment.refresh_from_db()
        wait_for("the pod's state", lambda: _refreshed(assignment).pod_phase == "Running")
        # ... and a pod elsewhere with the same name and labels (anyone's to write) changes nothing: the agent
        # follows the cluster's own namespace (and its handlers take only that namespace's pods).
        core.create_namespaced_pod("elsewhere", {"metadata": {"name": "task-pod", "labels": labels},
                                                 "spec": {**spec, "nodeName": names[2]}})  # fmt: skip
        core.patch_namespaced_pod_status("task-pod", "elsewhere", {"status": {"phase": "Failed"}})
        families = scrape_until(f"http://127.0.0.1:{port}/metrics", lambda f: total(
            f, "continuum_cluster_agent_events_total", cluster=str(cluster.pk), resource="pod") >= 2)  # fmt: skip
        assert total(families, "continuum_leader_election_master_status", name="continuum-cluster-agent") == 1
        assert total(families, "continuum_cluster_agent_events_total", cluster=str(cluster.pk), resource="nodes") >= 1
        a = _refreshed(assignment)
        assert (a.pod_phase, a.pod_node) == ("Running", names[0])
    finally:
        os.killpg(proc.pid, signal.SIGTERM)
        proc.wait(60)
        for name in names:
            core.delete_node(name)
        core.delete_namespace("elsewhere")
        core.delete_collection_namespaced_pod(NS)
        admin.close()
    text = log.read_text()
    assert "Forbidden" not in text and "403" not in text, text[-3000:]


def _refreshed(row):
    row.refresh_from_db()
    return row


def _holder(admin) -> str | None:
    try:
        return client.CoordinationV1Api(admin).read_namespaced_lease("continuum-cluster-agent", NS).spec.holder_identity
    except client.ApiException:
        return None
