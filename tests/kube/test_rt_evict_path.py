"""The eviction path of RT-Kube's reconcile worker against the session's real cluster (issue 15): the stage times
each eviction keeps, the taint written after the DELETE when our own active taint covers the node (and put back
if someone removed it meanwhile), a redelivered task that evicts nothing twice, and the warm-up of a cluster's
API connection (a dead API is reported, never fatal)."""

import time

import pytest

from apps.realtime.models import MonitoringReport, NodeTaint, RTEvent, RTPod, RTPolicy
from apps.realtime.monitoring import STAGES, ingest, parse_batch
from apps.realtime.tasks import rt_reconcile, rt_warm
from tests.kubeapi import free_port, kubeconfig_text
from tests.realtime.conftest import RT_NODES

pytestmark = [pytest.mark.kube, pytest.mark.django_db(transaction=True)]
VIOLATION = ("rt.monitoring/violation", "true", "NoSchedule")


@pytest.fixture
def evict_cluster(kube_cluster, kube):
    """node0 holds a B violator and three stateless A pods: real (unbound) pods in the API, which the ledger
    says run on node0 (the reconcile reads the ledger, the DELETE names each pod's uid)."""
    for node in kube_cluster.nodes.all():
        node.criticality, node.rt = RT_NODES[node.name]
        node.save()
    # recreate_orphans off: a bare victim stays gone (a Deployment's would be recreated by its ReplicaSet).
    RTPolicy.objects.create(cluster=kube_cluster, taint_duration_s=600, recreate_orphans=False)
    ns = kube_cluster.namespace
    kube.create_namespace({"metadata": {"name": ns}})
    for name, crit in (("slam", "B"), ("aux-0", "A"), ("aux-1", "A"), ("aux-2", "A")):
        body = {"metadata": {"name": name}, "spec": {"containers": [{"name": name, "image": "registry.invalid/x:1"}]}}
        uid = kube.create_namespaced_pod(ns, body).metadata.uid
        RTPod.objects.create(cluster=kube_cluster, namespace=ns, name=name, uid=uid, node="node0", container_name=name,
                             criticality=crit, stateless=crit == "A", cpu=0.1, utilization=0.1,
                             scheduler_name="RT-scheduler")  # fmt: skip
    yield kube_cluster
    kept = [t for t in kube.read_node("node0").spec.taints or [] if (t.key, t.value, t.effect) != VIOLATION]
    kube.patch_node("node0", {"spec": {"taints": [t.to_dict() for t in kept] or None}})


def violation(cluster, n: int) -> int:
    """A stored, deferred violation of slam on node0 (as the endpoint stores it for a cluster with an API)."""
    report = {"node": "node0", "containerName": "slam", "pod": "slam", "missedDeadlinesPeriod": 20 + n,
              "missedDeadlinesTotal": 100 + n, "id": f"v{n}"}  # fmt: skip
    result = ingest(cluster, parse_batch([report]), defer=True)
    [pk] = result["pending"]
    return pk


def taints(kube, node="node0"):
    return [(t.key, t.value, t.effect) for t in kube.read_node(node).spec.taints or []]


def pods(kube, ns):
    return {p.metadata.name for p in kube.list_namespaced_pod(ns).items}


def test_evictions_keep_their_stages_and_a_covered_node_is_tainted_after_the_delete(evict_cluster, kube):
    cluster, ns = evict_cluster, evict_cluster.namespace
    first = violation(cluster, 1)
    queued = time.time()
    [pk] = rt_reconcile.apply(args=(cluster.pk, [first]), kwargs={"queued_at": queued}).result
    event = RTEvent.objects.get(pk=pk)
    assert event.kind == "eviction" and not event.eviction_error
    stages = event.response["stages"]
    assert set(stages) == set(STAGES)  # every stage (jsonb keeps no key order), each after the one before
    times = [stages[k] for k in STAGES]
    assert times == sorted(times)
    victim = event.victim.split("/")[1]
    assert victim not in pods(kube, ns) and VIOLATION in taints(kube)
    taint = NodeTaint.objects.get(event=event)
    assert taint.applied_at <= event.eviction_sent_at  # not covered yet: the taint first (Fig. 3.36)

    # Someone removes our taint in the API; the database still says it lasts. The next eviction on node0 deletes
    # first and writes the taint right after: it is back.
    kept = [t for t in kube.read_node("node0").spec.taints if (t.key, t.value, t.effect) != VIOLATION]
    kube.patch_node("node0", {"spec": {"taints": [t.to_dict() for t in kept]}})
    assert VIOLATION not in taints(kube)
    second = violation(cluster, 2)
    [pk2] = rt_reconcile.apply(args=(cluster.pk, [second])).result
    again = RTEvent.objects.get(pk=pk2)
    assert again.kind == "eviction" and not again.eviction_error and again.victim != event.victim
    assert "queued" not in again.response["stages"] and "picked" in again.response["stages"]
    assert again.victim.split("/")[1] not in pods(kube, ns)
    assert VIOLATION in taints(kube)
    taint2 = NodeTaint.objects.get(event=again)
    assert taint2.applied_at >= again.eviction_done_at and not taint2.error

    # A redelivered message (or the sweep) finds both reports claimed: nothing more is evicted.
    assert rt_reconcile.apply(args=(cluster.pk, [first, second])).result == []
    assert RTEvent.objects.filter(cluster=cluster, kind="eviction").count() == 2
    assert not MonitoringReport.objects.filter(pk__in=[first, second], reconciled_at__isnull=True).exists()
    assert len(pods(kube, ns)) == 2  # slam and the last stateless pod


def test_warm_opens_the_api_connection_and_reports_a_dead_api(evict_cluster, kube_admin, kube_server, settings):
    from apps.clusters.models import Cluster

    assert rt_warm.apply(args=([evict_cluster.pk],)).result == 1
    assert rt_warm.apply().result == 1  # None: every cluster with an RT policy
    settings.CONTINUUM_KUBE_RETRY_DEADLINE_S = 1
    dead = kubeconfig_text(f"https://127.0.0.1:{free_port()}", "token", kube_server.ca_path.read_bytes())
    pk = kube_admin.post("/api/v1/clusters/import/", {"name": "gone", "kubeconfig": dead, "nodes": [{"name": "n1"}]},
                         format="json").data["id"]  # fmt: skip
    RTPolicy.objects.create(cluster=Cluster.objects.get(pk=pk))
    assert rt_warm.apply(args=([evict_cluster.pk, pk],)).result == 1

    from apps.realtime.kube import kube_for

    assert kube_for(evict_cluster).version()["gitVersion"].startswith("v1.")
