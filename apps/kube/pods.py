"""Pods of a pushed schedule: one pod per task, bound to its node through the Binding API.

"HEFT on Kubernetes" (thesis §3.3.2, spec 02 §7.1/§7.3): only the mapping of a schedule is pushed, one pod
per task pinned to its node; precedence is left to the tasks' publish/subscribe communication. Continuum is
the scheduler of the pods it creates: each pod names ``settings.CONTINUUM_SCHEDULER_NAME`` as its
``schedulerName`` (so kube-scheduler leaves it alone) and is bound to the chosen node through the Binding
API (``pods/binding``), like the bind phase of a secondary scheduler (spec 03 §4.4). Following spec 02
§7.3: pods use the host network (ROS nodes talk across machines), carry no CPU limits (CFS quotas would
override niceness) and are created in decreasing rank order (a push has up to
``CONTINUUM_KUBE_PUSH_CONCURRENCY`` creates and binds in flight, started in that order). Everything here is
idempotent, call by call: a retried create or bind never makes a second pod or moves one.

Takes engine types (:class:`~continuum.engine.core.schedule.Assignment`) and a :class:`PodSet` (which
schedule, which application, which namespace) and returns an :class:`Outcome` per assignment; the app that
stores schedules records them.
"""

from __future__ import annotations

import hashlib
import logging
import re
from collections.abc import Mapping
from dataclasses import dataclass, field

from django.conf import settings
from kubernetes import client
from kubernetes.client.exceptions import ApiException

from continuum.engine.core.schedule import Assignment
from continuum.engine.heft4k.heft4k import nice_container

from . import nodes, parallel
from .connect import API_ERRORS, REQUEST_TIMEOUT, by_label, call, describe, read_json
from .resources import pod_event

log = logging.getLogger(__name__)

#: Label and annotation prefix of everything Continuum writes.
PREFIX = "continuum.io"
MANAGED_BY = {"app.kubernetes.io/managed-by": "continuum"}


def dns_part(text: str, limit: int) -> str:
    """``text`` as a DNS-1123 label fragment of at most ``limit`` characters (never empty)."""
    part = re.sub(r"[^a-z0-9-]+", "-", text.lower()).strip("-")
    return part[:limit].strip("-") or "x"


def label_value(text: str) -> str:
    """A valid label value (<= 63 chars of [A-Za-z0-9-_.], alphanumeric at both ends)."""
    value = re.sub(r"[^A-Za-z0-9._-]+", "-", text)[:63]
    return re.sub(r"^[^A-Za-z0-9]+|[^A-Za-z0-9]+$", "", value)


@dataclass(frozen=True)
class PodSet:
    """Whose pods: the schedule and application ids (labels), the application's name (pod names), the upward
    ranks (annotations) and the namespace."""

    schedule: int
    application: int
    application_name: str
    namespace: str
    ranks: Mapping[str, float] = field(default_factory=dict)


@dataclass
class Outcome:
    ok: bool
    message: str


def pod_name(pods: PodSet, task: str, frame: int) -> str:
    """``<application>-<task>-<frame>-<hash>``: DNS-1123 safe, at most 63 characters, unique per
    (schedule, task, frame) thanks to the hash even when two task ids sanitize alike."""
    digest = hashlib.sha256(f"{pods.schedule}/{pods.application}/{task}/{frame}".encode()).hexdigest()[:10]
    return f"{dns_part(pods.application_name, 20)}-{dns_part(task, 24)}-{frame}-{digest}"


def pod_manifest(pods: PodSet, assignment: Assignment, name: str, *, host_network: bool = True) -> client.V1Pod:
    """The pod of one assignment: no ``nodeName`` (the binding sets it), Continuum's scheduler name."""
    labels = {
        **MANAGED_BY,
        f"{PREFIX}/schedule": str(pods.schedule),
        f"{PREFIX}/application": str(pods.application),
        f"{PREFIX}/task": label_value(assignment.task),
        f"{PREFIX}/frame": str(assignment.frame),
    }
    annotations = {
        f"{PREFIX}/task": assignment.task,
        f"{PREFIX}/node": assignment.processor,
        f"{PREFIX}/start": repr(assignment.start),
        f"{PREFIX}/finish": repr(assignment.finish),
    }
    if assignment.task in (pods.ranks or {}):
        annotations[f"{PREFIX}/rank"] = repr(pods.ranks[assignment.task])
    if assignment.niceness is not None:
        annotations[f"{PREFIX}/niceness"] = str(assignment.niceness)
    env = [
        client.V1EnvVar(name="CONTINUUM_TASK", value=assignment.task),
        client.V1EnvVar(name="CONTINUUM_FRAME", value=str(assignment.frame)),
        client.V1EnvVar(name="CONTINUUM_SCHEDULE", value=str(pods.schedule)),
    ]
    return client.V1Pod(
        api_version="v1",
        kind="Pod",
        metadata=client.V1ObjectMeta(name=name, labels=labels, annotations=annotations),
        spec=client.V1PodSpec(
            scheduler_name=settings.CONTINUUM_SCHEDULER_NAME,
            restart_policy="Never",
            host_network=host_network,
            containers=[_container(assignment, env)],
        ),
    )


def _container(assignment: Assignment, env: list) -> client.V1Container:
    """The task's container; with a niceness (HEFT4K, Eq. 3.16) its command runs under ``nice``, with
    ``SYS_NICE`` when negative (the engine's :func:`nice_container`, whose docstring lists the limits)."""
    container = client.V1Container(name="task", image=settings.CONTINUUM_POD_IMAGE, env=env)
    if assignment.niceness is not None:
        spec = nice_container(
            assignment.niceness, settings.CONTINUUM_POD_COMMAND, nice_binary=settings.CONTINUUM_NICE_BINARY
        )
        container.command = spec["command"]
        container.args = spec["args"] or None
        added = spec["securityContext"].get("capabilities", {}).get("add")
        if added:
            container.security_context = client.V1SecurityContext(capabilities=client.V1Capabilities(add=added))
    return container


def ensure_namespace(api_client: client.ApiClient, namespace: str) -> None:
    """Create ``namespace`` (labelled as Continuum's) unless it exists."""
    api = client.CoreV1Api(api_client)
    try:
        call(api.read_namespace, namespace, what=f"read namespace {namespace}")
        return
    except ApiException as exc:
        if exc.status != 404:
            raise
    body = client.V1Namespace(metadata=client.V1ObjectMeta(name=namespace, labels=dict(MANAGED_BY)))
    try:
        # Idempotent: a retried create that the server had already done answers 409, which is "done".
        call(api.create_namespace, body, what=f"create namespace {namespace}")
    except ApiException as exc:
        if exc.status != 409:  # created meanwhile by someone else (or by our own earlier attempt): fine
            raise


def drain(response) -> bytes:
    """Read a raw answer (``_preload_content=False``) to its end and give its connection back to the pool."""
    data = response.data
    response.release_conn()
    return data


class Pusher:
    """Places the pods of one :class:`PodSet`; one instance per push. Each placement returns an Outcome."""

    def __init__(self, pods: PodSet, api_client: client.ApiClient) -> None:
        self.pods = pods
        self.namespace = pods.namespace
        self.api_client = api_client
        self.api = client.CoreV1Api(api_client)
        self.server = api_client.configuration.host

    def ensure_namespace(self) -> None:
        ensure_namespace(self.api_client, self.namespace)

    def node_problems(self) -> dict[str, str | None]:
        return nodes.node_problems(self.api_client)

    def ready_nodes(self) -> set[str]:
        return nodes.ready_nodes(self.api_client)

    def existing_pods(self) -> dict[str, dict]:
        """The application's pods by name, as the server's JSON (:func:`~apps.kube.connect.by_label`): a
        remapped schedule keeps pods created for the schedule it came from."""
        return by_label(
            self.api.list_namespaced_pod,
            self.namespace,
            f"{PREFIX}/application={self.pods.application}",
            what=f"list pods in namespace {self.namespace}",
            server=self.server,
        )

    def _read_pod(self, name: str) -> dict:
        return call(
            read_json, self.api.read_namespaced_pod, name, self.namespace, what=f"read pod {name}", server=self.server
        )

    def place(self, assignment: Assignment, name: str, pod: dict | None, problems: dict[str, str | None]) -> Outcome:
        """Create ``name`` unless ``pod`` (its JSON, from :meth:`existing_pods`) exists, then bind it to the
        assignment's node unless it is bound there already."""
        node = assignment.processor
        if pod is not None and (mismatch := self._mismatch(pod, name, assignment)):
            return Outcome(False, mismatch)  # listed under the application's label, but another task's pod
        bound_to = _node_name(pod)
        if bound_to:
            if bound_to == node:
                return Outcome(True, f"bound to {node}")
            return Outcome(False, f"pod {name} is already bound to node {bound_to!r}, not {node!r}")
        if node not in problems:
            return Outcome(False, f"node {node!r} not found in the Kubernetes API")
        if problems[node]:
            return Outcome(False, problems[node])
        if pod is None:
            try:
                # The answer (the pod) is not used: read raw, not parsed into models (a V1Pod costs about as
                # much CPU to build as the round trip takes, and the push's threads share one interpreter).
                drain(
                    call(
                        self.api.create_namespaced_pod,
                        self.namespace,
                        pod_manifest(self.pods, assignment, name),
                        _preload_content=False,
                        what=f"create pod {name}",
                        server=self.server,
                    )
                )
            except ApiException as exc:
                if exc.status != 409:
                    return Outcome(False, f"pod {name} refused: {describe(exc)}")
                # Created meanwhile (a re-delivered job running twice, or our own attempt whose answer was
                # lost and retried): done if that pod is this assignment's, then bind it or find it bound.
                mismatch = self._not_ours(name, assignment)
                if mismatch:
                    return Outcome(False, mismatch)
        return self.bind(name, node)

    def _not_ours(self, name: str, assignment: Assignment) -> str | None:
        """Why the existing pod ``name`` is not the pod of ``assignment`` (``None``: it is)."""
        return self._mismatch(self._read_pod(name), name, assignment)

    def _mismatch(self, pod: dict, name: str, assignment: Assignment) -> str | None:
        """Why the pod ``pod`` (its JSON; named ``name``) is not the pod of ``assignment`` (``None``: it is)."""
        metadata = pod.get("metadata") or {}
        annotations = metadata.get("annotations") or {}
        labels = metadata.get("labels") or {}
        if (
            annotations.get(f"{PREFIX}/task") != assignment.task
            or labels.get(f"{PREFIX}/frame") != str(assignment.frame)
            or labels.get(f"{PREFIX}/application") != str(self.pods.application)
        ):
            return f"pod {name} already exists and is not the pod of task {assignment.task!r}"
        return None

    def bind(self, name: str, node: str) -> Outcome:
        body = client.V1Binding(
            api_version="v1",
            kind="Binding",
            metadata=client.V1ObjectMeta(name=name),
            target=client.V1ObjectReference(api_version="v1", kind="Node", name=node),
        )
        try:
            # The client cannot parse the Status a binding answers with: read the raw response.
            # Idempotent: a retried binding the server had already done answers 409, checked below.
            response = call(
                self.api.create_namespaced_pod_binding,
                name,
                self.namespace,
                body,
                _preload_content=False,
                what=f"bind pod {name} to node {node}",
                server=self.server,
            )
        except ApiException as exc:
            if exc.status == 409:
                if _node_name(self._read_pod(name)) == node:
                    return Outcome(True, f"bound to {node}")
                return Outcome(False, f"binding refused: {describe(exc)}")
            return Outcome(False, f"binding refused: {describe(exc)}")
        answer = drain(response)
        if response.status != 201:
            return Outcome(False, f"binding refused: HTTP {response.status} {answer[:200]!r}")
        self.scheduled_event(name, node)
        return Outcome(True, f"bound to {node}")

    def scheduled_event(self, name: str, node: str) -> None:
        """Record the binding as kube-scheduler does, a ``Scheduled`` Event on the pod (the pod's live state
        shows it: a hollow node's kubelet reports no events of its own). Best effort: the pod is bound anyway."""
        message = f"Successfully assigned {self.namespace}/{name} to {node}"
        body = pod_event(self.namespace, name, "Scheduled", message, settings.CONTINUUM_SCHEDULER_NAME)
        try:
            drain(
                self.api.create_namespaced_event(
                    self.namespace, body, _request_timeout=REQUEST_TIMEOUT, _preload_content=False
                )
            )
        except API_ERRORS as exc:
            log.warning("pod %s bound to %s, but its Scheduled event was refused: %s", name, node, describe(exc))

    def delete(self, name: str, *, force: bool) -> bool:
        """Delete a pod; ``force`` (grace period 0) for a pod on a node that is not Ready (or gone), whose
        kubelet cannot confirm the deletion. Returns whether the pod existed."""
        body = client.V1DeleteOptions(grace_period_seconds=0) if force else None
        try:
            self.api.delete_namespaced_pod(name, self.namespace, body=body, _request_timeout=REQUEST_TIMEOUT)
        except ApiException as exc:
            if exc.status == 404:
                return False
            raise
        return True


def _node_name(pod: dict | None) -> str:
    """The node a pod (its JSON) is bound to ('': none, or no pod)."""
    return ((pod or {}).get("spec") or {}).get("nodeName") or ""


def push(
    pods: PodSet,
    api_client: client.ApiClient,
    placements: list[tuple[Assignment, str]],
    progress=None,
    *,
    workers: int | None = None,
) -> tuple[list[Outcome], str | None]:
    """Place every ``(assignment, pod name)``, at most ``workers`` (``CONTINUUM_KUBE_PUSH_CONCURRENCY``) at a
    time, started in the given order (:mod:`apps.kube.parallel`); returns one Outcome per placement, in order,
    and, when the API went away (or refuses us wholesale), why (every placement not done yet then fails with
    that reason).

    Safe to repeat and to retry call by call: pod names are deterministic (:func:`pod_name`), a create answered
    409 adopts the existing pod only if it is this assignment's, a Binding answered 409 is done if the pod is
    bound to the same node; so a create whose answer was lost and is retried never makes a second pod."""
    progress = progress or (lambda percent, message: None)
    pusher = Pusher(pods, api_client)
    total = len(placements)
    try:
        # Independent reads at once (listing pods in a namespace not created yet answers an empty list).
        _, problems, existing = parallel.gather(pusher.ensure_namespace, pusher.node_problems, pusher.existing_pods)
    except API_ERRORS as exc:
        reason = describe(exc, pusher.server)
        return [Outcome(False, reason)] * total, reason
    progress(5, f"namespace {pusher.namespace}: {len(existing)} of {total} pods exist")
    return parallel.run_bounded(
        placements,
        lambda work: pusher.place(work[0], work[1], existing.get(work[1]), problems),
        skipped=lambda reason: Outcome(False, reason),
        fatal=API_ERRORS,
        describe=lambda exc: describe(exc, pusher.server),
        workers=workers,
        progress=lambda done: progress(5 + 90 * done / total, f"placed {done}/{total} pods"),
    )
