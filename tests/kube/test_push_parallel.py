"""Concurrent pushes (issue 15): bounded concurrency, idempotent retries, no duplicate pods, clear errors.

Against the session's real multi-node cluster: pods are bound to its hollow nodes (whose kubelets run them) or,
for the job through the API, to the ``kube_cluster`` fixture's synthetic nodes. A spy around the gateway's
``call`` (it delegates every call to the real API) counts the calls in flight and, where a test needs it,
makes a conflict happen for real at a given moment: the pod created by someone else just before our create, or
the API server's answer held back by a loopback proxy until our client times out.
"""

import contextlib
import socket
import threading
import time
import uuid

import pytest
from kubernetes import client

from tests.kube.conftest import MULTINODE_VICTIM, SESSION_NODES
from tests.kubeapi import kubeconfig_text

pytestmark = [pytest.mark.kube, pytest.mark.django_db]

TIMEOUT = 180  # generous: a loaded 2-core machine; tests wait for conditions, never for fixed times


def wait_for(what: str, check, timeout: float = TIMEOUT):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if value := check():
            return value
        time.sleep(0.25)
    pytest.fail(f"timed out after {timeout} s waiting for {what}")


def pod_set(namespace: str, application: int | None = None):
    from apps.kube.pods import PodSet

    app = application or uuid.uuid4().int % 10**6
    return PodSet(schedule=app, application=app, application_name="parallel push", namespace=namespace)


def live_hollow_nodes(api_client) -> list[str]:
    """The session's hollow nodes that are Ready, schedulable and untainted (a kubelet runs what is bound there,
    and kube-scheduler may place a Deployment's pod there)."""
    from apps.kube import gateway

    nodes = sorted(
        gateway.name_of(obj)
        for obj in gateway.list_nodes(api_client)
        if gateway.name_of(obj) in SESSION_NODES
        and gateway.name_of(obj) != MULTINODE_VICTIM
        and gateway.node_status(obj) == gateway.READY
        and not (obj.get("spec") or {}).get("unschedulable")
        and not gateway.taints_of(obj)
    )
    assert nodes, f"no healthy hollow node among {sorted(SESSION_NODES)}"
    return nodes


def work(pods, nodes: list[str], m: int) -> list:
    from apps.kube.pods import pod_name
    from continuum.engine.core.schedule import Assignment

    out = []
    for i in range(m):
        a = Assignment(task=f"task {i}", processor=nodes[i % len(nodes)], start=float(i), finish=i + 1.0)
        out.append((a, pod_name(pods, a.task, a.frame)))
    return out


def our_pods(kube, namespace: str, pods) -> dict:
    selector = f"continuum.io/application={pods.application}"
    return {p.metadata.name: p for p in kube.list_namespaced_pod(namespace, label_selector=selector).items}


class Spy:
    """Wraps ``apps.kube.pods.call`` (or ``module.call``): every call goes to the real API; records the pod
    creates in flight at once (``peak``) and the attempts per call; ``before(what, fn)`` runs ``fn`` once just
    before the first attempt of the call named ``what``; ``hold`` keeps each pod create in flight a little
    longer so overlap is observable."""

    def __init__(self, monkeypatch, hold: float = 0.0, module=None) -> None:
        from apps.kube import pods as pods_module

        module = module or pods_module  # the gateway module whose calls are watched (pods, or deployments)
        self.real = module.call
        self.hold = hold
        self.lock = threading.Lock()
        self.in_flight = 0
        self.peak = 0
        self.attempts: dict[str, int] = {}
        self.hooks: dict[str, object] = {}
        self.threads: set[int] = set()
        monkeypatch.setattr(module, "call", self.call)

    def before(self, what: str, fn) -> None:
        self.hooks[what] = fn

    def call(self, fn, *args, what: str, **kwargs):
        creating = what.startswith("create pod ")
        hook = self.hooks.pop(what, None)

        def attempt(*a, **kw):
            with self.lock:
                self.attempts[what] = self.attempts.get(what, 0) + 1
            return fn(*a, **kw)

        if creating:
            with self.lock:
                self.in_flight += 1
                self.peak = max(self.peak, self.in_flight)
                self.threads.add(threading.get_ident())
        try:
            if hook is not None:
                hook(kwargs)
            if creating and self.hold:
                time.sleep(self.hold)
            return self.real(attempt, *args, what=what, **kwargs)
        finally:
            if creating:
                with self.lock:
                    self.in_flight -= 1


def test_a_push_has_at_most_the_setting_in_flight_and_every_pod_runs(
    kubeconfig, kube, kube_namespace, settings, monkeypatch
):
    from apps.kube import gateway

    settings.CONTINUUM_KUBE_PUSH_CONCURRENCY = 3
    spy = Spy(monkeypatch, hold=0.3)
    pods = pod_set(kube_namespace)
    seen: list[tuple[float, str, int]] = []
    with gateway.api_client(kubeconfig, name="session") as api_client:
        placements = work(pods, live_hollow_nodes(api_client), 12)
        outcomes, fatal = gateway.push(
            pods, api_client, placements, lambda p, m: seen.append((p, m, threading.get_ident()))
        )
    assert fatal is None
    assert [o.ok for o in outcomes] == [True] * 12, [o.message for o in outcomes]
    assert spy.peak == 3  # overlapping (the 0.3 s hold makes that certain), never more than the setting
    assert len(spy.threads) == 3
    # Progress: from the caller's thread (a job's progress writes to the database), rising to every pod placed.
    assert {t for _, _, t in seen} == {threading.get_ident()}
    percents = [p for p, _, _ in seen]
    assert percents == sorted(percents) and percents[-1] == 95
    assert seen[-1][1] == "placed 12/12 pods"
    live = our_pods(kube, kube_namespace, pods)
    assert len(live) == 12
    for a, name in placements:
        assert live[name].spec.node_name == a.processor
    wait_for(
        "the 12 pods to run on the hollow nodes",
        lambda: sum(p.status.phase == "Running" for p in our_pods(kube, kube_namespace, pods).values()) == 12,
    )


def test_pods_made_before_and_during_a_concurrent_push_are_adopted_not_duplicated(
    kubeconfig, kube, kube_namespace, settings, monkeypatch
):
    """As when a create reached the server but its answer was lost, before the push listed the pods (the pod
    exists) and while it runs (the create answers 409): each pod is made once, kept (same uid) and bound."""
    from apps.kube import gateway
    from apps.kube.pods import pod_manifest

    settings.CONTINUUM_KUBE_PUSH_CONCURRENCY = 4
    spy = Spy(monkeypatch)
    pods = pod_set(kube_namespace)
    kube.create_namespace(client.V1Namespace(metadata=client.V1ObjectMeta(name=kube_namespace)))
    with gateway.api_client(kubeconfig, name="session") as api_client:
        placements = work(pods, live_hollow_nodes(api_client), 10)
        (early, early_name), (late, late_name) = placements[1], placements[6]
        made = {early_name: kube.create_namespaced_pod(kube_namespace, pod_manifest(pods, early, early_name))}

        def conflict(_kwargs):
            made[late_name] = kube.create_namespaced_pod(kube_namespace, pod_manifest(pods, late, late_name))

        spy.before(f"create pod {late_name}", conflict)
        outcomes, fatal = gateway.push(pods, api_client, placements)
    assert fatal is None
    assert all(o.ok for o in outcomes), [o.message for o in outcomes]
    assert spy.attempts[f"create pod {late_name}"] == 1  # answered 409: adopted, not retried into a second pod
    assert f"create pod {early_name}" not in spy.attempts  # listed: never created again
    live = our_pods(kube, kube_namespace, pods)
    assert sorted(live) == sorted(name for _, name in placements)  # exactly one pod per assignment
    for name, pod in made.items():
        assert live[name].metadata.uid == pod.metadata.uid
    for a, name in placements:
        assert live[name].spec.node_name == a.processor


class HoldingProxy:
    """A loopback TCP proxy to the API server; after :meth:`arm`, the next answer the server sends is held back
    and the connection dropped ``hold`` seconds later (an answer lost on a busy network: the request was done)."""

    def __init__(self, port: int, hold: float) -> None:
        self.target, self.hold = ("127.0.0.1", port), hold
        self.armed = threading.Event()
        self.held = 0
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.sockets: list[socket.socket] = []
        threading.Thread(target=self._accept, daemon=True).start()

    def arm(self) -> None:
        self.armed.set()

    def _accept(self) -> None:
        while True:
            try:
                conn, _ = self.listener.accept()
            except OSError:
                return
            upstream = socket.create_connection(self.target, timeout=30)
            upstream.settimeout(None)
            self.sockets += [conn, upstream]
            threading.Thread(target=self._pipe, args=(conn, upstream, False), daemon=True).start()
            threading.Thread(target=self._pipe, args=(upstream, conn, True), daemon=True).start()

    def _pipe(self, src: socket.socket, dst: socket.socket, answers: bool) -> None:
        try:
            while data := src.recv(65536):
                if answers and self.armed.is_set():
                    self.armed.clear()
                    self.held += 1
                    time.sleep(self.hold)
                    break  # the answer is never delivered
                dst.sendall(data)
        except OSError:
            pass
        finally:
            for s in (src, dst):
                with contextlib.suppress(OSError):
                    s.shutdown(socket.SHUT_RDWR)

    def close(self) -> None:
        """Stop listening and cut every connection (shutdown first: a bare close() does not wake a thread
        blocked in accept() or recv(), and the socket would go on serving)."""
        for s in [self.listener, *self.sockets]:
            with contextlib.suppress(OSError):
                s.shutdown(socket.SHUT_RDWR)
            with contextlib.suppress(OSError):
                s.close()


@contextlib.contextmanager
def answer_lost_once(kube_server, spy: Spy, call: str):
    """An API client whose requests go through a :class:`HoldingProxy`: the answer to the first attempt of the
    spied ``call`` reaches the server, but the client gives up on it after 1 s (the proxy holds it 4 s and drops
    the connection). Run the push with one worker, so the armed proxy holds exactly that call's answer."""
    from apps.kube import gateway

    proxy = HoldingProxy(kube_server.port, hold=4.0)

    def lose_the_answer(kwargs):
        kwargs["_request_timeout"] = (5, 1)  # (connect, read) seconds
        proxy.arm()

    spy.before(call, lose_the_answer)
    try:
        text = kubeconfig_text(f"https://127.0.0.1:{proxy.port}", kube_server.token, kube_server.ca_path.read_bytes())
        with gateway.api_client(text, name="through a proxy") as api_client:
            yield api_client
    finally:
        proxy.close()
    assert proxy.held == 1


def test_a_create_that_timed_out_after_the_server_made_the_pod_is_retried_without_a_duplicate(
    kube, kube_namespace, kube_server, settings, monkeypatch
):
    from apps.kube import gateway

    settings.CONTINUUM_KUBE_RETRY_BASE_S = 0.05
    spy = Spy(monkeypatch)
    pods = pod_set(kube_namespace)
    placements = work(pods, live_hollow_nodes(kube.api_client), 4)
    target = placements[2][1]
    with answer_lost_once(kube_server, spy, f"create pod {target}") as api_client:
        outcomes, fatal = gateway.push(pods, api_client, placements, workers=1)
    assert fatal is None
    assert all(o.ok for o in outcomes), [o.message for o in outcomes]
    assert spy.attempts[f"create pod {target}"] == 2  # timed out, retried, answered 409 ...
    assert spy.attempts[f"read pod {target}"] == 1  # ... and adopted after checking it is this assignment's
    live = our_pods(kube, kube_namespace, pods)
    assert sorted(live) == sorted(name for _, name in placements)
    for a, name in placements:
        assert live[name].spec.node_name == a.processor


def test_placement_errors_are_reported_per_pod_while_the_others_are_bound(kubeconfig, kube, kube_namespace, settings):
    from apps.kube import gateway
    from apps.kube.pods import pod_manifest
    from continuum.engine.core.schedule import Assignment

    settings.CONTINUUM_KUBE_PUSH_CONCURRENCY = 4
    pods = pod_set(kube_namespace)
    kube.create_namespace(client.V1Namespace(metadata=client.V1ObjectMeta(name=kube_namespace)))
    with gateway.api_client(kubeconfig, name="session") as api_client:
        placements = work(pods, live_hollow_nodes(api_client), 8)
        lost = Assignment(task="task 3", processor="no-such-node", start=3.0, finish=4.0)
        placements[3] = (lost, placements[3][1])
        squatted_name = placements[5][1]
        # Another task's pod squatting the name this assignment's pod must have: never adopted.
        kube.create_namespaced_pod(kube_namespace, pod_manifest(pods, placements[0][0], squatted_name))
        outcomes, fatal = gateway.push(pods, api_client, placements)
    assert fatal is None
    assert outcomes[3].message == "node 'no-such-node' not found in the Kubernetes API" and not outcomes[3].ok
    assert not outcomes[5].ok
    assert outcomes[5].message == f"pod {squatted_name} already exists and is not the pod of task 'task 5'"
    assert [i for i, o in enumerate(outcomes) if o.ok] == [0, 1, 2, 4, 6, 7]
    live = our_pods(kube, kube_namespace, pods)
    assert placements[3][1] not in live
    assert not live[squatted_name].spec.node_name


def test_when_the_api_goes_away_mid_push_the_rest_fail_with_the_reason(
    kube, kube_namespace, kube_server, settings, monkeypatch
):
    from apps.kube import gateway

    settings.CONTINUUM_KUBE_RETRY_DEADLINE_S = 2
    settings.CONTINUUM_KUBE_RETRY_BASE_S = 0.05
    settings.CONTINUUM_KUBE_PUSH_CONCURRENCY = 2
    spy = Spy(monkeypatch)
    pods = pod_set(kube_namespace)
    proxy = HoldingProxy(kube_server.port, hold=0)
    text = kubeconfig_text(f"https://127.0.0.1:{proxy.port}", kube_server.token, kube_server.ca_path.read_bytes())
    with gateway.api_client(text, name="through a proxy") as api_client:
        placements = work(pods, live_hollow_nodes(api_client), 12)
        spy.before(f"create pod {placements[4][1]}", lambda _kwargs: proxy.close())
        began = time.monotonic()
        outcomes, fatal = gateway.push(pods, api_client, placements)
    assert time.monotonic() - began < TIMEOUT  # bounded by the retry deadline, not hanging
    assert fatal is not None and "gave up after" in fatal and "Kubernetes API unreachable" in fatal, fatal
    # Two workers take the placements in order: when placement 4 starts, 0-3 have all started and the other
    # worker holds at most one of them (which one is a race), so at least three of them are done; 4 and the
    # one beside it in flight fail; none after them is started, each says why.
    assert sum(o.ok for o in outcomes[:4]) >= 3
    assert 3 <= sum(o.ok for o in outcomes) <= 4
    for o in outcomes:
        assert o.ok or o.message == fatal or "gave up after" in o.message, o.message
    assert [o.message for o in outcomes[6:]] == [fatal] * 6
    assert set(our_pods(kube, kube_namespace, pods)) <= {name for _, name in placements[:6]}


def test_the_push_job_binds_concurrently_and_reports_progress(api, kube, kube_cluster, kube_namespace, settings):
    from apps.jobs.models import Job
    from apps.scheduling.models import Schedule

    settings.CONTINUUM_KUBE_PUSH_CONCURRENCY = 4
    dag = {
        "format": "continuum.dag/v1",
        "name": "wide",
        "tasks": [{"id": "src", "cost": {"cpu": 1}}, *({"id": f"w{i}", "cost": {"cpu": 5 + i}} for i in range(16))],
        "edges": [{"src": "src", "dst": f"w{i}", "data": 0.1} for i in range(16)],
    }
    response = api.post("/api/v1/applications/", {"name": "wide", "dag": dag}, format="json")
    assert response.status_code == 201, response.data
    response = api.post(
        f"/api/v1/applications/{response.data['id']}/schedule/", {"cluster": kube_cluster.pk}, format="json"
    )
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded", job
    schedule = Schedule.objects.get(pk=job["result"]["schedule"])
    response = api.post(f"/api/v1/schedules/{schedule.pk}/push/", {}, format="json")
    assert response.status_code == 202, response.data
    pushed = Job.objects.get(pk=response.data["id"])
    assert pushed.state == Job.State.SUCCEEDED, pushed.error
    assert pushed.progress == 100
    assert pushed.result["bound"] == pushed.result["pods"] == 17
    pods = {p.metadata.name: p for p in kube.list_namespaced_pod(kube_namespace).items}
    assert len(pods) == 17
    for a in schedule.assignments.all():
        assert a.placement == "bound", a.placement_message
        assert pods[a.pod_name].spec.node_name == a.processor


def deployment(namespace: str, name: str, node: str, image: str = "registry.k8s.io/pause:3.9") -> dict:
    import hashlib
    import json

    body = {
        "apiVersion": "apps/v1",
        "kind": "Deployment",
        "metadata": {"name": name, "namespace": namespace, "labels": {"continuum.io/group": "parallel"},
                     "annotations": {}},
        "spec": {
            "replicas": 1,
            "selector": {"matchLabels": {"continuum.io/deployment": name}},
            "template": {
                "metadata": {"labels": {"continuum.io/deployment": name}},
                "spec": {"nodeSelector": {"kubernetes.io/hostname": node},
                         "containers": [{"name": "c", "image": image}]},
            },
        },
    }  # fmt: skip
    body["metadata"]["annotations"]["continuum.io/spec-hash"] = hashlib.sha256(
        json.dumps(body, sort_keys=True).encode()
    ).hexdigest()
    return body


def test_deployments_are_applied_concurrently_once_each_and_run(kubeconfig, kube, kube_namespace, settings):
    from kubernetes.client import AppsV1Api

    from apps.kube import gateway

    settings.CONTINUUM_KUBE_PUSH_CONCURRENCY = 3
    with gateway.api_client(kubeconfig, name="session") as api_client:
        nodes = live_hollow_nodes(api_client)
        apps = AppsV1Api(api_client)
        pusher = gateway.Deployments(api_client, kube_namespace, "continuum.io/spec-hash")
        pusher.ensure_namespace()
        bodies = [deployment(kube_namespace, f"d{i}", nodes[i % len(nodes)]) for i in range(7)]
        # Made already, as by an earlier attempt whose answer was lost: the same manifest, and an older one.
        apps.create_namespaced_deployment(kube_namespace, bodies[2])
        apps.create_namespaced_deployment(kube_namespace, deployment(kube_namespace, "d4", nodes[0], image="old"))
        done: list[int] = []
        results, fatal = pusher.apply_all([(b, None) for b in bodies], done.append)
    assert fatal is None
    assert (
        results
        == [(True, "created")] * 2
        + [(True, "unchanged"), (True, "created"), (True, "updated")]
        + [(True, "created")] * 2
    )
    assert done == list(range(1, 8))
    live = {d.metadata.name: d for d in AppsV1Api(kube.api_client).list_namespaced_deployment(kube_namespace).items}
    assert sorted(live) == [f"d{i}" for i in range(7)]
    assert live["d4"].spec.template.spec.containers[0].image == "registry.k8s.io/pause:3.9"

    def running() -> bool:
        pods = kube.list_namespaced_pod(kube_namespace).items
        return sum(p.status.phase == "Running" and p.metadata.deletion_timestamp is None for p in pods) == 7

    wait_for("one Running pod per Deployment, placed by kube-scheduler", running)


def deployment_pods(kube, namespace: str, name: str) -> list:
    """The live (not terminating) pods of the Deployment ``name``."""
    pods = kube.list_namespaced_pod(namespace, label_selector=f"continuum.io/deployment={name}").items
    return [p for p in pods if p.metadata.deletion_timestamp is None]


def test_a_deployment_create_that_timed_out_after_the_server_made_it_is_retried_without_a_duplicate(
    kube, kube_namespace, kube_server, settings, monkeypatch
):
    """The create reached the server, its answer was lost (held by the proxy until the client timed out): the
    retried create answers 409, the Deployment there is compared by hash and kept. One Deployment, one
    ReplicaSet, one pod each."""
    from kubernetes.client import AppsV1Api

    from apps.kube import deployments as deployments_module
    from apps.kube import gateway

    settings.CONTINUUM_KUBE_RETRY_BASE_S = 0.05
    spy = Spy(monkeypatch, module=deployments_module)
    nodes = live_hollow_nodes(kube.api_client)
    bodies = [deployment(kube_namespace, f"d{i}", nodes[i % len(nodes)]) for i in range(3)]
    with answer_lost_once(kube_server, spy, "create Deployment d1") as api_client:
        pusher = gateway.Deployments(api_client, kube_namespace, "continuum.io/spec-hash")
        pusher.ensure_namespace()
        results, fatal = pusher.apply_all([(b, None) for b in bodies], workers=1)
    assert fatal is None
    # d1: timed out, retried, answered 409, read once and found to be this manifest (by its hash): kept as it is.
    assert results == [(True, "created"), (True, "unchanged"), (True, "created")]
    assert spy.attempts["create Deployment d1"] == 2
    assert spy.attempts["read Deployment d1"] == 1
    assert "replace Deployment d1" not in spy.attempts
    apps = AppsV1Api(kube.api_client)
    assert sorted(d.metadata.name for d in apps.list_namespaced_deployment(kube_namespace).items) == ["d0", "d1", "d2"]
    for name in ("d0", "d1", "d2"):
        sets = apps.list_namespaced_replica_set(kube_namespace, label_selector=f"continuum.io/deployment={name}").items
        assert len(sets) <= 1, [s.metadata.name for s in sets]  # the controller may not have made it yet
    wait_for(
        "one Running pod per Deployment",
        lambda: all(
            [p.status.phase for p in deployment_pods(kube, kube_namespace, f"d{i}")] == ["Running"] for i in range(3)
        ),
    )
    for name in ("d0", "d1", "d2"):
        sets = apps.list_namespaced_replica_set(kube_namespace, label_selector=f"continuum.io/deployment={name}").items
        assert len(sets) == 1, [s.metadata.name for s in sets]
        assert len(deployment_pods(kube, kube_namespace, name)) == 1


def rolled_out(apps, namespace: str, name: str) -> bool:
    d = apps.read_namespaced_deployment(name, namespace)
    return (d.status.observed_generation or 0) >= d.metadata.generation and (d.status.available_replicas or 0) == 1


def test_a_deployment_replace_that_timed_out_after_the_server_did_it_is_retried_as_done(
    kube, kube_namespace, kube_server, settings, monkeypatch
):
    """The replace reached the server, its answer was lost: the retried replace (same resourceVersion) answers
    409, the fresh read carries our hash, so it is done. Still one Deployment, and one pod running the new
    manifest once the rollout ends."""
    from kubernetes.client import AppsV1Api

    from apps.kube import deployments as deployments_module
    from apps.kube import gateway

    settings.CONTINUUM_KUBE_RETRY_BASE_S = 0.05
    apps = AppsV1Api(kube.api_client)
    node = live_hollow_nodes(kube.api_client)[0]
    gateway.Deployments(kube.api_client, kube_namespace, "continuum.io/spec-hash").ensure_namespace()
    made = apps.create_namespaced_deployment(
        kube_namespace, deployment(kube_namespace, "d0", node, image="registry.k8s.io/pause:3.8")
    )
    # Once rolled out its status stops changing: the resourceVersion listed below is still current when the
    # replace is sent, so the first replace is done (not refused as stale) and only its answer lost.
    wait_for("the old Deployment to be available", lambda: rolled_out(apps, kube_namespace, "d0"))
    spy = Spy(monkeypatch, module=deployments_module)
    with answer_lost_once(kube_server, spy, "replace Deployment d0") as api_client:
        pusher = gateway.Deployments(api_client, kube_namespace, "continuum.io/spec-hash")
        current = pusher.existing("continuum.io/group=parallel")
        results, fatal = pusher.apply_all([(deployment(kube_namespace, "d0", node), current.get("d0"))], workers=1)
    assert fatal is None
    assert results == [(True, "updated")]
    assert spy.attempts["replace Deployment d0"] == 2  # timed out, retried: 409 (the first one had been done) ...
    assert spy.attempts["read Deployment d0"] == 1  # ... and read once: our hash is there
    live = apps.list_namespaced_deployment(kube_namespace).items
    assert [d.metadata.name for d in live] == ["d0"] and live[0].metadata.uid == made.metadata.uid
    assert live[0].spec.template.spec.containers[0].image == "registry.k8s.io/pause:3.9"
    wait_for(
        "the rollout to end with one Running pod of the new manifest",
        lambda: (
            [(p.status.phase, p.spec.containers[0].image) for p in deployment_pods(kube, kube_namespace, "d0")]
            == [("Running", "registry.k8s.io/pause:3.9")]
        ),
    )
