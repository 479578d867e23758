"""RT-Kube's calls through the gateway (bind, Events, eviction) are retried on transient failures and give up
with a clear error after the deadline (issue 12, "Robust on a busy machine").

Real parts only: the session cluster's kube-apiserver behind a loopback TCP proxy that resets the first
connections (tests/kube/test_gateway_retries.ResettingProxy: an RST right after accept, as an overloaded server
or middlebox does), the real client, and a hollow node that runs the pod. More connections are reset than the
client's own urllib3 retries (``connect=2``, ``read=0``: at most 3 attempts) could absorb, so a call that
succeeds was repeated by the gateway.
"""

import time

import pytest

from apps.clusters.kube import api_client_for
from apps.kube.gateway import Kube
from apps.kube.retry import GaveUp
from apps.realtime.models import NodeTaint, RTEvent, RTPod
from apps.realtime.monitoring import _evict
from tests.kube.conftest import running_on, wait_for
from tests.kube.test_gateway_retries import ResettingProxy
from tests.kubeapi import kubeconfig_text

pytestmark = [pytest.mark.kube, pytest.mark.django_db]
NODE = "hollow-a"
RESETS = 4


@pytest.fixture
def proxied(kube_admin, cluster, kube_server, settings):
    """The (model-only) cluster pointed at the session's API server through a :class:`ResettingProxy`."""
    settings.CONTINUUM_KUBE_RETRY_BASE_S = 0.05
    proxy = ResettingProxy(("127.0.0.1", kube_server.port), resets=0)
    text = kubeconfig_text(f"https://127.0.0.1:{proxy.port}", kube_server.token, kube_server.ca_path.read_bytes())
    response = kube_admin.patch(f"/api/v1/clusters/{cluster.pk}/", {"kubeconfig": text}, format="json")
    assert response.status_code == 200, response.data
    cluster.refresh_from_db()
    yield cluster, proxy
    proxy.close()


def fresh(cluster, proxy: ResettingProxy, resets: int) -> Kube:
    """A new client (no pooled connection: its first request opens one) after arming ``resets`` resets."""
    proxy.resets_left, proxy.reset = resets, 0
    return Kube(api_client_for(cluster), cluster.name, component="RT-scheduler")


def rt_pod(kube, namespace: str, name: str):
    kube.create_namespace({"metadata": {"name": namespace}})
    body = {
        "metadata": {"name": name, "labels": {"app": name}},
        "spec": {"schedulerName": "RT-scheduler", "containers": [{"name": name, "image": "registry.invalid/rt:1"}]},
    }
    return kube.create_namespaced_pod(namespace, body)


def test_bind_event_and_eviction_are_retried_through_reset_connections(kube, proxied, kube_namespace):
    cluster, proxy = proxied
    created = rt_pod(kube, kube_namespace, "cam")
    pod = {"metadata": {"namespace": kube_namespace, "name": "cam", "uid": created.metadata.uid}}

    ok, message = fresh(cluster, proxy, RESETS).bind(kube_namespace, "cam", NODE, created.metadata.uid)
    assert (ok, message) == (True, f"bound to {NODE}")
    assert proxy.reset == RESETS  # every reset connection was tried again by the gateway
    wait_for("the pod Running on the bound node", lambda: running_on(kube, kube_namespace) == {"cam": NODE})
    # A binding repeated after the server did it (its answer lost) answers 409: done, when bound there.
    again = fresh(cluster, proxy, 0).bind(kube_namespace, "cam", NODE, created.metadata.uid)
    assert again == (True, f"bound to {NODE}")
    refused, why = fresh(cluster, proxy, 0).bind(kube_namespace, "cam", "hollow-b", created.metadata.uid)
    assert not refused and "binding refused: Kubernetes API answered 409" in why

    fresh(cluster, proxy, RESETS).event(pod, "Scheduled", f"Successfully assigned {kube_namespace}/cam to {NODE}")
    assert proxy.reset == RESETS
    events = kube.list_namespaced_event(kube_namespace, field_selector="involvedObject.name=cam").items
    assert [e.reason for e in events if e.source.component == "RT-scheduler"] == ["Scheduled"]

    deleted = fresh(cluster, proxy, RESETS).delete_pod(kube_namespace, "cam", created.metadata.uid)
    assert deleted["metadata"]["uid"] == created.metadata.uid and proxy.reset == RESETS
    wait_for("the evicted pod gone", lambda: not kube.list_namespaced_pod(kube_namespace).items)


def test_an_api_that_keeps_failing_gives_up_at_the_deadline_naming_the_call(kube, proxied, kube_namespace, settings):
    cluster, proxy = proxied
    settings.CONTINUUM_KUBE_RETRY_DEADLINE_S = 2
    created = rt_pod(kube, kube_namespace, "arm")
    began = time.monotonic()
    with pytest.raises(GaveUp) as failed:
        fresh(cluster, proxy, 10**6).bind(kube_namespace, "arm", NODE, created.metadata.uid)
    assert time.monotonic() - began < 60  # bounded by the deadline (generous for a busy machine)
    message = str(failed.value)
    assert message.startswith(f"bind pod {kube_namespace}/arm to {NODE}: gave up after ")
    assert f"Kubernetes API unreachable at https://127.0.0.1:{proxy.port}" in message
    assert failed.value.attempts >= 2 and proxy.reset >= 2
    assert kube.read_namespaced_pod("arm", kube_namespace).spec.node_name is None  # nothing half-done

    # The eviction path records the same clear error on its event instead of raising.
    node = cluster.nodes.first()
    victim = RTPod.objects.create(cluster=cluster, namespace=kube_namespace, name="arm", uid=created.metadata.uid,
                                  node=node.name)  # fmt: skip
    event = RTEvent(cluster=cluster, kind=RTEvent.Kind.EVICTION, node=node.name, victim=victim.key)
    taint = NodeTaint(cluster=cluster, node=node, key="rt.monitoring/violation", value="true", effect="NoSchedule")
    proxy.resets_left = 10**6
    assert _evict(cluster, event, victim, taint) is None
    assert event.eviction_error.startswith(f"evict pod {kube_namespace}/arm: gave up after ")
    assert taint.error.startswith(f"taint node {node.name}: gave up after ")
    assert kube.read_namespaced_pod("arm", kube_namespace).metadata.deletion_timestamp is None
