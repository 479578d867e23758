"""The gateway retries idempotent calls on transient failures (issue 12, "Robust on a busy machine").

Real parts: the session cluster's kube-apiserver behind a loopback TCP proxy that resets the first connections, and, for
HTTP answers a real server only gives under load (503, 429), a tiny plain-HTTP API on loopback
(``CONTINUUM_KUBE_ALLOW_HTTP_LOOPBACK``) driven through the real client and gateway.
"""

import contextlib
import json
import socket
import struct
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest
from kubernetes import client
from kubernetes.client.exceptions import ApiException

from tests.kube.test_gateway import heft_schedule, pods_by_name, run
from tests.kubeapi import kubeconfig_text

pytestmark = [pytest.mark.kube, pytest.mark.django_db]

NODE_LIST = {
    "kind": "NodeList",
    "apiVersion": "v1",
    "metadata": {},
    "items": [
        {
            "metadata": {"name": "edge-1", "labels": {"kubernetes.io/arch": "amd64"}},
            "spec": {},
            "status": {
                "capacity": {"cpu": "4", "memory": "8Gi"},
                "conditions": [{"type": "Ready", "status": "True"}],
            },
        }
    ],
}


class FlakyAPI:
    """A plain-HTTP loopback API answering ``GET /api/v1/nodes``: the first answers come from ``script``
    (``(status, headers)``), then ``NODE_LIST``. Records when each request came."""

    def __init__(self, script: list[tuple[int, dict]]) -> None:
        self.script = list(script)
        self.times: list[float] = []
        fake = self

        class Handler(BaseHTTPRequestHandler):
            def do_GET(self):
                fake.times.append(time.monotonic())
                status, headers = fake.script.pop(0) if fake.script else (200, {})
                body = json.dumps(
                    NODE_LIST if status == 200 else {"kind": "Status", "message": f"injected {status}", "code": status}
                ).encode()
                self.send_response(status)
                for key, value in {"Content-Type": "application/json", **headers}.items():
                    self.send_header(key, value)
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)

            def log_message(self, *args):
                pass

        self.server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.url = f"http://127.0.0.1:{self.server.server_address[1]}"
        threading.Thread(target=self.server.serve_forever, daemon=True).start()

    def close(self) -> None:
        self.server.shutdown()
        self.server.server_close()


@pytest.fixture
def flaky(kube_admin, cluster, settings, kube_server):
    """``flaky(script)``: point the (model-only) cluster at a new :class:`FlakyAPI`; returns it."""
    settings.CONTINUUM_KUBE_ALLOW_HTTP_LOOPBACK = True
    settings.CONTINUUM_KUBE_RETRY_BASE_S = 0.05
    made = []

    def make(script):
        fake = FlakyAPI(script)
        made.append(fake)
        text = kubeconfig_text(fake.url, "token", kube_server.ca_path.read_bytes())
        response = kube_admin.patch(f"/api/v1/clusters/{cluster.pk}/", {"kubeconfig": text}, format="json")
        assert response.status_code == 200, response.data
        cluster.refresh_from_db()
        return fake

    yield make
    for fake in made:
        fake.close()


def test_sync_retries_503_and_504_and_gets_the_same_nodes(flaky, cluster):
    from apps.clusters import kube as cluster_kube

    fake = flaky([(503, {}), (504, {}), (502, {})])
    counts = cluster_kube.sync_nodes(cluster)
    assert len(fake.times) == 4  # three injected failures, then the answer
    assert counts["nodes"] == 1
    node = cluster.nodes.get(name="edge-1")
    assert node.status == "Ready" and node.cpu == 4 and node.memory_mib == 8192


def test_429_waits_as_long_as_retry_after_says(flaky, cluster):
    from apps.clusters import kube as cluster_kube

    fake = flaky([(429, {"Retry-After": "1"})])
    assert cluster_kube.sync_nodes(cluster)["nodes"] == 1
    assert len(fake.times) == 2
    assert fake.times[1] - fake.times[0] >= 0.9  # honoured the server's 1 s, not the 0.05 s base


def test_a_permanently_failing_api_fails_within_the_deadline_naming_the_call(flaky, cluster, settings):
    from apps.clusters import kube as cluster_kube
    from apps.kube import gateway

    settings.CONTINUUM_KUBE_RETRY_DEADLINE_S = 2
    fake = flaky([(503, {})] * 10_000)
    began = time.monotonic()
    with pytest.raises(gateway.KubeError) as failed:
        cluster_kube.sync_nodes(cluster)
    message = str(failed.value)
    assert message.startswith(f"cluster {cluster.name!r}: list nodes: gave up after ")
    assert "Kubernetes API answered 503: injected 503" in message
    assert len(fake.times) >= 2  # retried before giving up
    assert time.monotonic() - began < 60  # bounded by the deadline, not hanging (generous for a busy machine)
    assert not cluster.nodes.filter(name="edge-1").exists()


def test_other_4xx_answers_are_not_retried(flaky, cluster):
    from apps.clusters import kube as cluster_kube
    from apps.kube import gateway

    fake = flaky([(403, {}), (503, {})])
    with pytest.raises(gateway.KubeError, match="Kubernetes API answered 403: injected 403"):
        cluster_kube.sync_nodes(cluster)
    assert len(fake.times) == 1


def test_a_call_that_is_not_idempotent_is_not_repeated_after_a_5xx(flaky, cluster):
    from apps.clusters import kube as cluster_kube
    from apps.kube import gateway, retry

    fake = flaky([(503, {}), (429, {"Retry-After": "0"})])
    api = client.CoreV1Api(cluster_kube.api_client_for(cluster))
    with pytest.raises(ApiException) as failed:
        gateway.call(api.list_node, what="list nodes once", idempotent=False)
    assert failed.value.status == 503 and len(fake.times) == 1
    # 429 says the request was not processed: safe to repeat even so.
    assert gateway.call(api.list_node, what="list nodes once", idempotent=False).items[0].metadata.name == "edge-1"
    assert len(fake.times) == 3
    assert not retry.transient(ApiException(status=409), idempotent=True)


# -- a real kube-apiserver behind connections that are reset ------------------------------------------------


class ResettingProxy:
    """A loopback TCP proxy to ``target`` (host, port) that resets the first ``resets`` connections (RST right
    after accept, like an overloaded server or middlebox) and then forwards the TLS bytes untouched."""

    def __init__(self, target: tuple[str, int], resets: int) -> None:
        self.target, self.resets_left, self.reset = target, resets, 0
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.closed = False
        threading.Thread(target=self._accept, daemon=True).start()

    def _accept(self) -> None:
        while not self.closed:
            try:
                conn, _ = self.listener.accept()
            except OSError:
                return
            if self.resets_left > 0:
                self.resets_left -= 1
                self.reset += 1
                conn.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
                conn.close()
                continue
            upstream = socket.create_connection(self.target, timeout=30)
            upstream.settimeout(None)
            for a, b in ((conn, upstream), (upstream, conn)):
                threading.Thread(target=self._pipe, args=(a, b), daemon=True).start()

    @staticmethod
    def _pipe(src: socket.socket, dst: socket.socket) -> None:
        try:
            while data := src.recv(65536):
                dst.sendall(data)
        except OSError:
            pass
        finally:
            for s in (src, dst):
                with contextlib.suppress(OSError):
                    s.shutdown(socket.SHUT_RDWR)

    def close(self) -> None:
        self.closed = True
        self.listener.close()


def test_a_push_through_reset_connections_binds_every_pod(
    api, kube, kube_admin, kube_cluster, kube_namespace, kube_server
):
    from apps.clusters import kube as cluster_kube

    proxy = ResettingProxy(("127.0.0.1", kube_server.port), resets=3)
    try:
        text = kubeconfig_text(f"https://127.0.0.1:{proxy.port}", kube_server.token, kube_server.ca_path.read_bytes())
        response = kube_admin.patch(f"/api/v1/clusters/{kube_cluster.pk}/", {"kubeconfig": text}, format="json")
        assert response.status_code == 200, response.data
        kube_cluster.refresh_from_db()
        synced = cluster_kube.sync_nodes(kube_cluster)
        assert synced["nodes"] >= 4 and proxy.reset >= 1
        schedule = heft_schedule(api, kube_cluster)
        proxy.resets_left = 3  # and again in the middle of the push
        job = run(api, f"/api/v1/schedules/{schedule.pk}/push/")
    finally:
        proxy.close()
    assert job["state"] == "succeeded", job
    assert proxy.reset >= 4
    pods = pods_by_name(kube, kube_namespace)
    assignments = list(schedule.assignments.all())
    assert job["result"]["bound"] == len(assignments) == len(pods)
    for a in assignments:
        assert a.placement == "bound"
        assert pods[a.pod_name].spec.node_name == a.processor


def test_a_binding_answered_409_for_the_same_node_counts_as_done(api, kube, kube_cluster, kube_namespace):
    from apps.clusters import kube as cluster_kube
    from apps.scheduling import kube as schedule_kube

    schedule = heft_schedule(api, kube_cluster)
    assert run(api, f"/api/v1/schedules/{schedule.pk}/push/")["state"] == "succeeded"
    a = schedule.assignments.first()
    a.refresh_from_db()
    with cluster_kube.api_client_for(kube_cluster) as api_client:
        pusher = schedule_kube.pusher_for(schedule, api_client)
        # As when a retried binding reaches a server that had done the first one: 409, already bound there.
        again = pusher.bind(a.pod_name, a.processor)
        assert again.ok and again.message == f"bound to {a.processor}"
        other = next(n.name for n in kube_cluster.nodes.all() if n.name != a.processor)
        moved = pusher.bind(a.pod_name, other)
        assert not moved.ok and "binding refused: Kubernetes API answered 409" in moved.message
    assert pods_by_name(kube, kube_namespace)[a.pod_name].spec.node_name == a.processor


def test_a_pod_create_answered_409_is_done_only_if_the_pod_is_the_assignments(api, kube, kube_cluster, kube_namespace):
    from apps.clusters import kube as cluster_kube
    from apps.scheduling import kube as schedule_kube

    schedule = heft_schedule(api, kube_cluster)
    ours, theirs = list(schedule.assignments.all())[:2]
    kube.create_namespace(client.V1Namespace(metadata=client.V1ObjectMeta(name=kube_namespace)))
    # As when a create reached the server but its answer was lost: the pod exists, the push did not list it.
    ours_name = schedule_kube.pod_name(schedule, ours.task, ours.frame)
    kube.create_namespaced_pod(kube_namespace, schedule_kube.pod_manifest(schedule, ours, ours_name))
    # A pod of another task squatting the name: never adopted.
    theirs_name = schedule_kube.pod_name(schedule, theirs.task, theirs.frame)
    kube.create_namespaced_pod(kube_namespace, schedule_kube.pod_manifest(schedule, ours, theirs_name))
    with cluster_kube.api_client_for(kube_cluster) as api_client:
        pusher = schedule_kube.pusher_for(schedule, api_client)
        problems = pusher.node_problems()
        done = pusher.place(ours.to_engine(), ours_name, None, problems)
        refused = pusher.place(theirs.to_engine(), theirs_name, None, problems)
    assert done.ok and done.message == f"bound to {ours.processor}"
    assert not refused.ok
    assert refused.message == f"pod {theirs_name} already exists and is not the pod of task {theirs.task!r}"
    pods = pods_by_name(kube, kube_namespace)
    assert pods[ours_name].spec.node_name == ours.processor
    assert not pods[theirs_name].spec.node_name  # left alone, not bound


def test_a_certificate_from_another_ca_fails_at_once(kube_admin, cluster, kube_server, settings):
    """Certificate refusals are permanent: no waiting out the deadline before saying so."""
    import certifi

    from apps.clusters import kube as cluster_kube
    from apps.kube import gateway

    settings.CONTINUUM_KUBE_RETRY_DEADLINE_S = 600
    bundle = Path(certifi.where()).read_text()  # a public root CA: not the one that signed the test server
    begin = bundle.index("-----BEGIN CERTIFICATE-----")
    other_ca = bundle[begin : bundle.index("-----END CERTIFICATE-----", begin) + 25].encode() + b"\n"
    text = kubeconfig_text(kube_server.server, kube_server.token, other_ca)
    assert kube_admin.patch(f"/api/v1/clusters/{cluster.pk}/", {"kubeconfig": text}, format="json").status_code == 200
    cluster.refresh_from_db()
    began = time.monotonic()
    with pytest.raises(gateway.KubeError, match="CERTIFICATE_VERIFY_FAILED") as failed:
        cluster_kube.sync_nodes(cluster)
    assert "gave up" not in str(failed.value)
    assert time.monotonic() - began < 300  # far below the 600 s deadline: not retried
