"""Kubernetes gateway: read a cluster's nodes and push a schedule's placements as bound pods.

"HEFT on Kubernetes" (thesis §3.3.2, spec 02 §7.1/§7.3): only the mapping of a schedule is pushed, one pod
per task pinned to its node; precedence is left to the tasks' publish/subscribe communication. Continuum is
the scheduler of the pods it creates: each pod names ``settings.CONTINUUM_SCHEDULER_NAME`` as its
``schedulerName`` (so kube-scheduler leaves it alone) and is bound to the chosen node through the Binding
API (``pods/binding``), like the bind phase of a secondary scheduler (spec 03 §4.4). Following spec 02
§7.3: pods use the host network (ROS nodes talk across machines), carry no CPU limits (CFS quotas would
override niceness) and are created in decreasing rank order. Everything here is idempotent: syncing or
pushing twice leaves the cluster and the database as the first call did.
"""

from __future__ import annotations

import atexit
import contextlib
import hashlib
import json
import os
import re
import shutil
import tempfile
import threading
from collections.abc import Callable
from dataclasses import dataclass
from decimal import Decimal
from pathlib import Path

import urllib3
from django.conf import settings
from django.db import transaction
from django.utils import timezone
from kubernetes import client
from kubernetes.client.exceptions import ApiException
from kubernetes.utils import parse_quantity

from apps.clusters.models import Cluster, ComputeNode
from apps.scheduling.models import Assignment, Schedule
from continuum.engine.heft4k.heft4k import nice_container

from . import kubeconfig, retry
from .credentials import Undecryptable
from .kubeconfig import KubeconfigError, KubeTarget, ServerPolicy

#: (connect, read) seconds for every API call, so a black-holed API fails the job instead of hanging it.
REQUEST_TIMEOUT = (5, 30)
#: Label and annotation prefix of everything Continuum writes.
PREFIX = "continuum.io"
MANAGED_BY = {"app.kubernetes.io/managed-by": "continuum"}
#: Label keys that carry a node's CPU architecture (the first one present wins).
ARCH_LABELS = ("kubernetes.io/arch", "beta.kubernetes.io/arch")
ARCH_ALIASES = {"x86_64": "amd64", "aarch64": "arm64", "arm64v8": "arm64", "riscv": "riscv64"}
UNSCHEDULABLE_TAINT = {"key": "node.kubernetes.io/unschedulable", "value": "", "effect": "NoSchedule"}

Progress = Callable[[float, str], None]


class KubeError(ValueError):
    """The Kubernetes API cannot be used (no/bad kubeconfig, unreachable, refused): the job fails cleanly."""


#: What an API call may raise when the server is unreachable, refuses us, or stayed failing past the deadline.
API_ERRORS = (ApiException, urllib3.exceptions.HTTPError, OSError, retry.GaveUp)


def call(fn, *args, what: str, server: str = "", idempotent: bool = True, **kwargs):
    """``fn(*args, **kwargs)`` through :func:`apps.kube.retry.call` (transient failures retried with backoff
    until ``CONTINUUM_KUBE_RETRY_DEADLINE_S``), every attempt with :data:`REQUEST_TIMEOUT`."""
    kwargs.setdefault("_request_timeout", REQUEST_TIMEOUT)
    if not server:  # a bound method of a CoreV1Api: name its server in the error
        api_client = getattr(getattr(fn, "__self__", None), "api_client", None)
        server = getattr(getattr(api_client, "configuration", None), "host", "") or ""
    return retry.call(
        fn, *args, what=what, idempotent=idempotent, describe=lambda exc: describe(exc, server), **kwargs
    )


# -- connecting ---------------------------------------------------------------------------------------------


def server_policy() -> ServerPolicy:
    """Where kubeconfigs may point, from the settings (``CONTINUUM_KUBE_*``)."""
    return ServerPolicy(
        allow_http_loopback=settings.CONTINUUM_KUBE_ALLOW_HTTP_LOOPBACK,
        allowed_hosts=tuple(settings.CONTINUUM_KUBE_API_ALLOWED_HOSTS),
        max_bytes=settings.CONTINUUM_KUBECONFIG_MAX_BYTES,
    )


def target_for(cluster: Cluster) -> KubeTarget:
    """The cluster's validated API target. The stored kubeconfig is checked again on every load: rows saved
    before validation existed (or written to the database directly) get no pass."""
    text = cluster.kubeconfig
    if isinstance(text, Undecryptable):
        raise KubeError(
            f"cluster {cluster.name!r}: its kubeconfig cannot be decrypted with CONTINUUM_CREDENTIALS_KEY "
            "(was the key changed without keeping the old one?); set the kubeconfig again"
        )
    if not text.strip():
        raise KubeError(f"cluster {cluster.name!r} has no kubeconfig: it is a model-only cluster")
    try:
        return kubeconfig.validate(text, cluster.kube_context, server_policy())
    except KubeconfigError as exc:
        raise KubeError(f"cluster {cluster.name!r}: kubeconfig refused: {exc}") from exc


#: Client certificate files by content digest: urllib3 only loads them from files. Private directory (0700),
#: files 0600, removed at exit.
_CERT_DIR: list[Path] = []
_CERT_LOCK = threading.Lock()


def _private_file(data: bytes, suffix: str) -> str:
    with _CERT_LOCK:
        if not _CERT_DIR:
            _CERT_DIR.append(Path(tempfile.mkdtemp(prefix="continuum-kube-certs-")))
            atexit.register(shutil.rmtree, _CERT_DIR[0], True)
        path = _CERT_DIR[0] / f"{hashlib.sha256(data).hexdigest()}{suffix}"
        if not path.exists():
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
            with os.fdopen(fd, "wb") as out:
                out.write(data)
        return str(path)


def configuration_for(target: KubeTarget) -> client.Configuration:
    """The client configuration of a validated target, set field by field: no kubeconfig loader, so no exec
    plugin, auth provider or file path can ever come into play. TLS is always verified."""
    configuration = client.Configuration()
    configuration.host = target.server
    configuration.verify_ssl = True
    configuration.ca_cert_data = target.ca_pem  # None: the system's CAs
    configuration.tls_server_name = target.tls_server_name
    if target.token:
        configuration.api_key = {"authorization": f"Bearer {target.token}"}
    if target.client_cert_pem and target.client_key_pem:
        configuration.cert_file = _private_file(target.client_cert_pem, ".crt")
        configuration.key_file = _private_file(target.client_key_pem, ".key")
    # Retry refused/reset connections briefly; never re-send a request the server may have acted on. HTTP
    # answers (429/503 with Retry-After included) are left to :func:`call`, which knows what is idempotent:
    # urllib3 would otherwise turn a 429 into an exhausted-retries error without waiting.
    configuration.retries = urllib3.Retry(
        total=2, connect=2, read=0, status=0, other=0, backoff_factor=0.2, respect_retry_after_header=False
    )
    return configuration


def api_client_for(cluster: Cluster) -> client.ApiClient:
    """An API client for ``cluster`` from its validated kubeconfig and context (no global state). The one
    builder every caller uses (gateway, RT-Kube's JSON client, container pushes, HEFT4K)."""
    return client.ApiClient(configuration_for(target_for(cluster)))


def describe(exc: BaseException, server: str = "") -> str:
    """One line saying why a call failed: the API's own message, or why the server could not be reached."""
    if isinstance(exc, retry.GaveUp):
        return str(exc)  # already names the call and describes its last cause
    if isinstance(exc, ApiException):
        message = exc.reason or ""
        with contextlib.suppress(ValueError, AttributeError):  # not a Status document: keep the reason
            message = json.loads(exc.body or "{}").get("message") or message
        return f"Kubernetes API answered {exc.status}: {message}"
    if isinstance(exc, urllib3.exceptions.MaxRetryError) and exc.reason is not None:
        exc = exc.reason
    reason = str(exc)
    # urllib3 prefixes the connection object's repr; the tail is the useful part.
    if "): " in reason:
        reason = reason.rsplit("): ", 1)[-1]
    where = f" at {server}" if server else ""
    return f"Kubernetes API unreachable{where}: {reason}"


# -- syncing nodes ------------------------------------------------------------------------------------------


def _mib(quantity: str | None) -> int | None:
    if not quantity:
        return None
    return int(parse_quantity(quantity) / Decimal(2**20))


def _cores(quantity: str | None) -> float | None:
    return None if not quantity else float(parse_quantity(quantity))


def _arch(node) -> str | None:
    labels = node.metadata.labels or {}
    raw = next((labels[k] for k in ARCH_LABELS if labels.get(k)), None)
    if raw is None and node.status is not None and node.status.node_info is not None:
        raw = node.status.node_info.architecture
    if not raw:
        return None
    raw = raw.lower()
    return ARCH_ALIASES.get(raw, raw)[:16]


def node_status(node) -> str:
    """Ready/NotReady/Unknown from the node's Ready condition (no condition at all: Unknown)."""
    for condition in (node.status.conditions if node.status else None) or []:
        if condition.type == "Ready":
            return {"True": ComputeNode.Status.READY, "False": ComputeNode.Status.NOT_READY}.get(
                condition.status, ComputeNode.Status.UNKNOWN
            )
    return ComputeNode.Status.UNKNOWN


def node_fields(node) -> dict:
    """The ComputeNode fields a Kubernetes node determines; the rest (class, speed, rt...) stay Continuum's."""
    capacity = (node.status.capacity if node.status else None) or {}
    taints = [
        {"key": t.key, "value": t.value or "", "effect": t.effect}
        for t in (node.spec.taints if node.spec else None) or []
    ]
    if node.spec and node.spec.unschedulable and not any(t["key"] == UNSCHEDULABLE_TAINT["key"] for t in taints):
        # A cordoned node: the node lifecycle controller would add this taint; there may be none running.
        taints.append(dict(UNSCHEDULABLE_TAINT))
    fields = {"labels": dict(node.metadata.labels or {}), "taints": taints, "status": node_status(node)}
    for name, value in (
        ("arch", _arch(node)),
        ("cpu", _cores(capacity.get("cpu"))),
        ("memory_mib", _mib(capacity.get("memory"))),
        ("storage_mib", _mib(capacity.get("ephemeral-storage"))),
    ):
        if value is not None:
            fields[name] = value
    return fields


def sync_nodes(cluster: Cluster, progress: Progress | None = None) -> dict:
    """Create/update the cluster's ComputeNode rows from its API; nodes gone from the API become NotReady.

    Returns counts: ``{"nodes", "created", "updated", "unchanged", "gone"}``.
    """
    api_client = api_client_for(cluster)
    server = api_client.configuration.host
    try:
        with api_client:
            items = call(client.CoreV1Api(api_client).list_node, what="list nodes", server=server).items
    except API_ERRORS as exc:
        raise KubeError(f"cluster {cluster.name!r}: {describe(exc, server)}") from exc
    if progress:
        progress(50, f"read {len(items)} nodes")
    counts = {"nodes": len(items), "created": 0, "updated": 0, "unchanged": 0, "gone": 0}
    seen = set()
    with transaction.atomic():
        existing = {n.name: n for n in cluster.nodes.select_for_update()}
        for node in items:
            name = node.metadata.name
            seen.add(name)
            fields = node_fields(node)
            row = existing.get(name)
            if row is None:
                ComputeNode.objects.create(cluster=cluster, name=name, **fields)
                counts["created"] += 1
            elif any(getattr(row, k) != v for k, v in fields.items()):
                for key, value in fields.items():
                    setattr(row, key, value)
                row.save(update_fields=list(fields))
                counts["updated"] += 1
            else:
                counts["unchanged"] += 1
        for name, row in existing.items():
            if name not in seen and row.status != ComputeNode.Status.NOT_READY:
                # Kept, not deleted: links, schedules and history still refer to it.
                row.status = ComputeNode.Status.NOT_READY
                row.save(update_fields=["status"])
                counts["gone"] += 1
        cluster.last_synced = timezone.now()
        cluster.save(update_fields=["last_synced"])
    return counts


# -- pushing schedules --------------------------------------------------------------------------------------


def _dns_part(text: str, limit: int) -> str:
    part = re.sub(r"[^a-z0-9-]+", "-", text.lower()).strip("-")
    return part[:limit].strip("-") or "x"


def _label_value(text: str) -> str:
    """A valid label value (<= 63 chars of [A-Za-z0-9-_.], alphanumeric at both ends)."""
    value = re.sub(r"[^A-Za-z0-9._-]+", "-", text)[:63]
    return re.sub(r"^[^A-Za-z0-9]+|[^A-Za-z0-9]+$", "", value)


def pod_name(schedule: Schedule, task: str, frame: int) -> str:
    """``<application>-<task>-<frame>-<hash>``: DNS-1123 safe, at most 63 characters, unique per
    (schedule, task, frame) thanks to the hash even when two task ids sanitize alike."""
    digest = hashlib.sha256(f"{schedule.pk}/{schedule.application_id}/{task}/{frame}".encode()).hexdigest()[:10]
    app = _dns_part(schedule.application.name, 20)
    return f"{app}-{_dns_part(task, 24)}-{frame}-{digest}"


def pod_manifest(schedule: Schedule, assignment: Assignment, name: str, *, host_network: bool = True) -> client.V1Pod:
    """The pod of one assignment: no ``nodeName`` (the binding sets it), Continuum's scheduler name."""
    labels = {
        **MANAGED_BY,
        f"{PREFIX}/schedule": str(schedule.pk),
        f"{PREFIX}/application": str(schedule.application_id),
        f"{PREFIX}/task": _label_value(assignment.task),
        f"{PREFIX}/frame": str(assignment.frame),
    }
    annotations = {
        f"{PREFIX}/task": assignment.task,
        f"{PREFIX}/node": assignment.processor,
        f"{PREFIX}/start": repr(assignment.start),
        f"{PREFIX}/finish": repr(assignment.finish),
    }
    if assignment.task in (schedule.ranks or {}):
        annotations[f"{PREFIX}/rank"] = repr(schedule.ranks[assignment.task])
    if assignment.niceness is not None:
        annotations[f"{PREFIX}/niceness"] = str(assignment.niceness)
    env = [
        client.V1EnvVar(name="CONTINUUM_TASK", value=assignment.task),
        client.V1EnvVar(name="CONTINUUM_FRAME", value=str(assignment.frame)),
        client.V1EnvVar(name="CONTINUUM_SCHEDULE", value=str(schedule.pk)),
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


def ensure_namespace(api: client.CoreV1Api, namespace: str) -> None:
    """Create ``namespace`` (labelled as Continuum's) unless it exists."""
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


def node_problems(api: client.CoreV1Api) -> dict[str, str | None]:
    """Every node of the API mapped to why a pod may not go there (``None``: it may)."""
    problems: dict[str, str | None] = {}
    for node in call(api.list_node, what="list nodes").items:
        problem = None
        if node_status(node) == ComputeNode.Status.NOT_READY:
            problem = f"node {node.metadata.name!r} is NotReady"
        elif node.spec and node.spec.unschedulable:
            problem = f"node {node.metadata.name!r} is cordoned (unschedulable)"
        problems[node.metadata.name] = problem
    return problems


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


@dataclass
class Outcome:
    ok: bool
    message: str


class Pusher:
    """Pushes one schedule; one instance per push. Records an Outcome per assignment."""

    def __init__(self, schedule: Schedule, api_client: client.ApiClient) -> None:
        self.schedule = schedule
        self.cluster = schedule.cluster
        self.namespace = self.cluster.namespace or settings.CONTINUUM_DEFAULT_NAMESPACE
        self.api = client.CoreV1Api(api_client)
        self.server = api_client.configuration.host

    def ensure_namespace(self) -> None:
        ensure_namespace(self.api, self.namespace)

    def node_problems(self) -> dict[str, str | None]:
        return node_problems(self.api)

    def existing_pods(self) -> dict[str, object]:
        """The application's pods by name: a remapped schedule keeps pods created for the schedule it came from."""
        selector = f"{PREFIX}/application={self.schedule.application_id}"
        pods = call(
            self.api.list_namespaced_pod,
            self.namespace,
            label_selector=selector,
            what=f"list pods in namespace {self.namespace}",
            server=self.server,
        ).items
        return {p.metadata.name: p for p in pods}

    def place(self, assignment: Assignment, name: str, pod, problems: dict[str, str | None]) -> Outcome:
        node = assignment.processor
        if pod is not None and pod.spec.node_name:
            if pod.spec.node_name == node:
                return Outcome(True, f"bound to {node}")
            return Outcome(False, f"pod {name} is already bound to node {pod.spec.node_name!r}, not {node!r}")
        if node not in problems:
            return Outcome(False, f"node {node!r} not found in the Kubernetes API")
        if problems[node]:
            return Outcome(False, problems[node])
        if pod is None:
            try:
                call(
                    self.api.create_namespaced_pod,
                    self.namespace,
                    pod_manifest(self.schedule, assignment, name),
                    what=f"create pod {name}",
                    server=self.server,
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
        pod = call(self.api.read_namespaced_pod, name, self.namespace, what=f"read pod {name}", server=self.server)
        annotations = pod.metadata.annotations or {}
        labels = pod.metadata.labels or {}
        if (
            annotations.get(f"{PREFIX}/task") != assignment.task
            or labels.get(f"{PREFIX}/frame") != str(assignment.frame)
            or labels.get(f"{PREFIX}/application") != str(self.schedule.application_id)
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
                bound = call(
                    self.api.read_namespaced_pod, name, self.namespace, what=f"read pod {name}", server=self.server
                )
                if bound.spec.node_name == node:
                    return Outcome(True, f"bound to {node}")
                return Outcome(False, f"binding refused: {describe(exc)}")
            return Outcome(False, f"binding refused: {describe(exc)}")
        answer = response.data  # read it all, so the connection goes back to the pool
        response.release_conn()
        if response.status != 201:
            return Outcome(False, f"binding refused: HTTP {response.status} {answer[:200]!r}")
        return Outcome(True, f"bound to {node}")


def _save(assignment: Assignment, placement: str, message: str, name: str) -> None:
    assignment.placement = placement
    assignment.placement_message = message[:500]
    assignment.pod_name = name


def push_schedule(schedule: Schedule, progress: Progress | None = None) -> dict:
    """One pod per assignment in ``cluster.namespace``, bound to the assigned node; returns a summary.

    Records ``placement`` (bound/failed), ``placement_message`` and ``pod_name`` on every assignment.
    Raises :class:`KubeError` with a summary if any placement failed (the rows are stored first).
    """
    progress = progress or (lambda percent, message: None)
    cluster = schedule.cluster
    if cluster is None:
        raise KubeError(f"schedule {schedule.pk} was computed on a platform document, not on a cluster")
    api_client = api_client_for(cluster)
    ranks = schedule.ranks or {}
    # Highest upward rank first (spec 02 §7.3); ties by start time, then task id, for a stable order.
    assignments = sorted(schedule.assignments.all(), key=lambda a: (-ranks.get(a.task, 0.0), a.start, a.task, a.frame))
    # A task kept by a remap (apps.heft4k) still runs in the pod of the earlier schedule: keep its name.
    names = {a.pk: a.pod_name or pod_name(schedule, a.task, a.frame) for a in assignments}
    outcomes: dict[int, Outcome] = {}
    with api_client:
        pusher = Pusher(schedule, api_client)
        try:
            pusher.ensure_namespace()
            problems = pusher.node_problems()
            pods = pusher.existing_pods()
            progress(5, f"namespace {pusher.namespace}: {len(pods)} of {len(assignments)} pods exist")
            for i, assignment in enumerate(assignments, 1):
                name = names[assignment.pk]
                outcomes[assignment.pk] = pusher.place(assignment, name, pods.get(name), problems)
                progress(5 + 90 * i / len(assignments), f"placed {i}/{len(assignments)} pods")
        except API_ERRORS as exc:
            # The API went away (or refuses us wholesale): every placement not done yet fails with the reason.
            reason = describe(exc, pusher.server)
            for assignment in assignments:
                outcomes.setdefault(assignment.pk, Outcome(False, reason))
            fatal = reason
        else:
            fatal = None
    for assignment in assignments:
        outcome = outcomes[assignment.pk]
        placement = Assignment.Placement.BOUND if outcome.ok else Assignment.Placement.FAILED
        _save(assignment, placement, outcome.message, names[assignment.pk])
    with transaction.atomic():
        Assignment.objects.bulk_update(assignments, ["placement", "placement_message", "pod_name"])
    failed = [a for a in assignments if not outcomes[a.pk].ok]
    summary = {
        "schedule": schedule.pk,
        "namespace": pusher.namespace,
        "pods": len(assignments),
        "bound": len(assignments) - len(failed),
        "failed": len(failed),
    }
    if failed:
        raise KubeError(_failure_summary(schedule, cluster, failed, len(assignments), fatal))
    return summary


def _failure_summary(schedule, cluster, failed: list[Assignment], total: int, fatal: str | None) -> str:
    if fatal:
        return f"push of schedule {schedule.pk} to cluster {cluster.name!r} failed: {fatal}"
    reasons: dict[str, list[str]] = {}
    for a in failed:
        reasons.setdefault(a.placement_message, []).append(a.task if a.frame == 0 else f"{a.task}#{a.frame}")
    parts = []
    for reason, tasks in sorted(reasons.items(), key=lambda kv: -len(kv[1])):
        shown = ", ".join(tasks[:5]) + (f" and {len(tasks) - 5} more" if len(tasks) > 5 else "")
        parts.append(f"{reason} (tasks {shown})")
    return f"{len(failed)} of {total} placements of schedule {schedule.pk} failed: " + "; ".join(parts)
