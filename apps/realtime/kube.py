"""RT-Kube's calls to a cluster's Kubernetes API, as plain JSON (thesis 3.4, Fig. 3.32; spec 03 sections 3, 4.4, 5.4).

Everything goes through :class:`Kube`, a thin JSON client on the cluster's ``ApiClient`` (from
:func:`apps.kube.gateway.api_client_for`, the one builder: server, credentials and TLS come from the validated
kubeconfig, never from the kubeconfig loader): no generated model classes, so custom objects, Bindings and
Status answers need no special handling and large pod lists parse quickly.

- The two CustomResourceDefinitions (apiextensions v1, with status subresources): ``realtimes.rt.scheduling``
  (Listing 3.33) and ``monitorings.rt.monitoring`` (Listing 3.37).
- The bind phase (``pods/binding``), the scheduler's explanations (a ``FailedScheduling`` Event and the
  ``PodScheduled`` condition), the eviction (``DELETE`` with grace period 0) and node taints, written with
  optimistic concurrency (the node's ``resourceVersion``) and retried on conflicts.
"""

from __future__ import annotations

import copy
import hashlib
import json
import threading
import time
from collections.abc import Iterable
from datetime import UTC, datetime
from typing import Any

import urllib3
from kubernetes.client import ApiClient
from kubernetes.client.exceptions import ApiException

from apps.clusters.models import Cluster
from apps.kube.gateway import REQUEST_TIMEOUT, KubeError, api_client_for, describe
from continuum.engine.rtkube.rt_model import RT_SCHEDULER_NAME

REALTIME_GROUP, REALTIME_VERSION, REALTIME_PLURAL = "rt.scheduling", "v1", "realtimes"
MONITORING_GROUP, MONITORING_VERSION, MONITORING_PLURAL = "rt.monitoring", "v1alpha1", "monitorings"
MERGE_PATCH = "application/merge-patch+json"
JSON_PATCH = "application/json-patch+json"
STRATEGIC_PATCH = "application/strategic-merge-patch+json"
#: Node labels that carry the RT attributes Continuum keeps (spec 03 3.3 [PROPOSAL]).
CRITICALITY_LABEL = "rt.scheduling/criticality"
THRESHOLD_LABEL = "rt.scheduling/threshold"

#: What a call to the API may raise: an error answer, an unreachable server, an unusable kubeconfig.
KUBE_ERRORS = (ApiException, OSError, urllib3.exceptions.HTTPError, ValueError)


def problem(exc: BaseException) -> str:
    """One line saying why a call failed."""
    if isinstance(exc, ApiException | OSError | urllib3.exceptions.HTTPError):
        return describe(exc)
    return str(exc)


_POSITIVE = {"type": "number", "minimum": 0, "exclusiveMinimum": True}


def _crd(group: str, version: str, plural: str, kind: str, short: str, spec: dict, columns: list) -> dict:
    return {
        "apiVersion": "apiextensions.k8s.io/v1",
        "kind": "CustomResourceDefinition",
        "metadata": {"name": f"{plural}.{group}", "labels": {"app.kubernetes.io/managed-by": "continuum"}},
        "spec": {
            "group": group,
            "scope": "Namespaced",
            "names": {"plural": plural, "singular": kind.lower(), "kind": kind, "shortNames": [short]},
            "versions": [
                {
                    "name": version,
                    "served": True,
                    "storage": True,
                    "subresources": {"status": {}},
                    "additionalPrinterColumns": columns,
                    "schema": {
                        "openAPIV3Schema": {
                            "type": "object",
                            "required": ["spec"],
                            "properties": {
                                "spec": spec,
                                "status": {"type": "object", "x-kubernetes-preserve-unknown-fields": True},
                            },
                        }
                    },
                }
            ],
        },
    }


def crd_manifests() -> list[dict]:
    """The RealTime and Monitoring CRDs with OpenAPI schemas (enum criticality, positive numbers, unique nodes)."""
    realtime_spec = {
        "type": "object",
        "required": ["criticality", "rtPeriod", "rtDeadline", "rtWcets"],
        "properties": {
            # D exists on the ASIL-derived scale but needs an ASIL-D capable platform (thesis 3.4).
            "criticality": {"type": "string", "enum": ["A", "B", "C"]},
            "rtPeriod": dict(_POSITIVE, description="period P (ms)"),
            "rtDeadline": dict(_POSITIVE, description="relative deadline D <= P (ms)"),
            "rtWcets": {
                "type": "array",
                "minItems": 1,
                # A list keyed by node: the API server rejects a node given twice.
                "x-kubernetes-list-type": "map",
                "x-kubernetes-list-map-keys": ["node"],
                "items": {
                    "type": "object",
                    "required": ["node", "rtWcet"],
                    "properties": {
                        "node": {"type": "string", "minLength": 1},
                        "rtWcet": dict(_POSITIVE, description="WCET on this node, <= D (ms)"),
                    },
                },
            },
            "stateless": {"type": "boolean"},
            "cpu": dict(_POSITIVE, description="CPU request (cores)"),
            "memoryMib": dict(_POSITIVE, description="memory request (MiB)"),
        },
    }
    monitoring_spec = {
        "type": "object",
        "required": ["node", "containerName", "missedDeadlinesPeriod", "missedDeadlinesTotal"],
        "properties": {
            "node": {"type": "string", "minLength": 1},
            "containerName": {"type": "string", "minLength": 1},
            "pod": {"type": "string"},
            "missedDeadlinesPeriod": {"type": "integer", "minimum": 0},
            "missedDeadlinesTotal": {"type": "integer", "minimum": 0},
            "sentAt": {"type": "string"},
            "missAt": {"type": "string"},
        },
    }
    return [
        _crd(
            REALTIME_GROUP,
            REALTIME_VERSION,
            REALTIME_PLURAL,
            "RealTime",
            "rt",
            realtime_spec,
            [
                {"name": "Criticality", "type": "string", "jsonPath": ".spec.criticality"},
                {"name": "Period", "type": "number", "jsonPath": ".spec.rtPeriod"},
                {"name": "Deadline", "type": "number", "jsonPath": ".spec.rtDeadline"},
            ],
        ),
        _crd(
            MONITORING_GROUP,
            MONITORING_VERSION,
            MONITORING_PLURAL,
            "Monitoring",
            "rtmon",
            monitoring_spec,
            [
                {"name": "Node", "type": "string", "jsonPath": ".spec.node"},
                {"name": "Container", "type": "string", "jsonPath": ".spec.containerName"},
                {"name": "Period", "type": "integer", "jsonPath": ".spec.missedDeadlinesPeriod"},
                {"name": "Total", "type": "integer", "jsonPath": ".spec.missedDeadlinesTotal"},
            ],
        ),
    ]


def now_rfc3339() -> str:
    return datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


class Kube:
    """JSON access to one cluster's API server."""

    def __init__(self, api_client: ApiClient, name: str = "") -> None:
        self.api_client = api_client
        self.name = name
        self.server = api_client.configuration.host

    # ---- plumbing ------------------------------------------------------------------------------------
    def request(
        self,
        method: str,
        path: str,
        body: Any = None,
        query: dict | None = None,
        content_type: str = "application/json",
        timeout: Any = REQUEST_TIMEOUT,
    ) -> Any:
        """One call; the decoded JSON answer, or :class:`ApiException` for an HTTP error status."""
        headers = {"Accept": "application/json"}
        if body is not None:
            headers["Content-Type"] = content_type  # the client serializes the body itself
        params = [(k, v) for k, v in (query or {}).items() if v is not None]
        method, url, headers, body, _ = self.api_client.param_serialize(
            method, path, query_params=params, header_params=headers, body=body, auth_settings=["BearerToken"]
        )
        response = self.api_client.call_api(method, url, header_params=headers, body=body, _request_timeout=timeout)
        data = response.read()
        response.response.release_conn()
        if not 200 <= response.status < 300:
            text = data.decode(errors="replace") if isinstance(data, bytes) else str(data)
            raise ApiException(status=response.status, reason=response.reason, body=text)
        return json.loads(data) if data else None

    def get(self, path: str, **query) -> Any:
        return self.request("GET", path, query=query)

    def exists(self, path: str) -> bool:
        try:
            self.get(path)
            return True
        except ApiException as exc:
            if exc.status == 404:
                return False
            raise

    # ---- namespaces and CRDs ---------------------------------------------------------------------------
    def ensure_namespace(self, namespace: str) -> None:
        if self.exists(f"/api/v1/namespaces/{namespace}"):
            return
        body = {"apiVersion": "v1", "kind": "Namespace", "metadata": {"name": namespace}}
        try:
            self.request("POST", "/api/v1/namespaces", body)
        except ApiException as exc:
            if exc.status != 409:
                raise

    def install_crds(self, wait: float = 20.0) -> list[str]:
        """Create or update both CRDs and wait until they are Established; returns what changed."""
        changed = []
        base = "/apis/apiextensions.k8s.io/v1/customresourcedefinitions"
        for crd in crd_manifests():
            name = crd["metadata"]["name"]
            try:
                current = self.get(f"{base}/{name}")
            except ApiException as exc:
                if exc.status != 404:
                    raise
                self.request("POST", base, crd)
                changed.append(f"created {name}")
                continue
            if (
                current.get("spec", {}).get("versions") != crd["spec"]["versions"]
                or current["spec"].get("names", {}).get("shortNames") != crd["spec"]["names"]["shortNames"]
            ):
                body = copy.deepcopy(crd)
                body["metadata"]["resourceVersion"] = current["metadata"]["resourceVersion"]
                self.request("PUT", f"{base}/{name}", body)
                changed.append(f"updated {name}")
        deadline = time.monotonic() + wait
        for crd in crd_manifests():
            name = crd["metadata"]["name"]
            while True:
                conditions = (self.get(f"{base}/{name}").get("status") or {}).get("conditions") or []
                if any(c.get("type") == "Established" and c.get("status") == "True" for c in conditions):
                    break
                if time.monotonic() > deadline:
                    raise KubeError(f"CRD {name} is not Established after {wait:g} s")
                time.sleep(0.1)
        return changed

    # ---- custom objects --------------------------------------------------------------------------------
    @staticmethod
    def _objects_path(group: str, version: str, plural: str, namespace: str | None) -> str:
        if namespace is None:
            return f"/apis/{group}/{version}/{plural}"
        return f"/apis/{group}/{version}/namespaces/{namespace}/{plural}"

    def list_objects(self, group: str, version: str, plural: str, namespace: str | None) -> list[dict]:
        return self.get(self._objects_path(group, version, plural, namespace)).get("items") or []

    def get_object(self, group: str, version: str, plural: str, namespace: str, name: str) -> dict | None:
        try:
            return self.get(f"{self._objects_path(group, version, plural, namespace)}/{name}")
        except ApiException as exc:
            if exc.status == 404:
                return None
            raise

    def put_object(self, group: str, version: str, plural: str, obj: dict) -> dict:
        """Create ``obj``, or replace the existing object's spec (keeping its status); returns the stored object."""
        namespace, name = obj["metadata"]["namespace"], obj["metadata"]["name"]
        path = self._objects_path(group, version, plural, namespace)
        for _ in range(5):
            current = self.get_object(group, version, plural, namespace, name)
            if current is None:
                try:
                    return self.request("POST", path, obj)
                except ApiException as exc:
                    if exc.status != 409:
                        raise
                    continue  # created meanwhile: replace it
            body = copy.deepcopy(obj)
            body["metadata"] = {**current["metadata"], **obj["metadata"]}
            body["metadata"]["resourceVersion"] = current["metadata"]["resourceVersion"]
            try:
                return self.request("PUT", f"{path}/{name}", body)
            except ApiException as exc:
                if exc.status != 409:
                    raise
        raise KubeError(f"{plural}/{name}: the object kept changing while we wrote it")

    def delete_object(self, group: str, version: str, plural: str, namespace: str, name: str) -> bool:
        try:
            self.request("DELETE", f"{self._objects_path(group, version, plural, namespace)}/{name}")
            return True
        except ApiException as exc:
            if exc.status == 404:
                return False
            raise

    def patch_status(self, group: str, version: str, plural: str, namespace: str, name: str, status: dict) -> None:
        path = f"{self._objects_path(group, version, plural, namespace)}/{name}/status"
        try:
            self.request("PATCH", path, {"status": status}, content_type=MERGE_PATCH)
        except ApiException as exc:
            if exc.status != 404:  # deleted meanwhile: nothing to annotate
                raise

    # ---- nodes -------------------------------------------------------------------------------------------
    def list_nodes(self) -> list[dict]:
        return self.get("/api/v1/nodes").get("items") or []

    def update_node(self, name: str, change) -> dict | None:
        """Read the node, let ``change(node)`` edit it (return False for no change), write it back; retried on
        conflicts thanks to the resourceVersion. Returns the node written (or read, when unchanged)."""
        for _ in range(8):
            try:
                node = self.get(f"/api/v1/nodes/{name}")
            except ApiException as exc:
                if exc.status == 404:
                    return None
                raise
            if change(node) is False:
                return node
            patch = {
                "metadata": {
                    "resourceVersion": node["metadata"]["resourceVersion"],
                    "labels": node["metadata"].get("labels") or {},
                },
                "spec": {"taints": node.get("spec", {}).get("taints") or None},
            }
            try:
                return self.request("PATCH", f"/api/v1/nodes/{name}", patch, content_type=MERGE_PATCH)
            except ApiException as exc:
                if exc.status != 409:
                    raise
        raise KubeError(f"node {name}: kept changing while we wrote its taints")

    def set_taint(self, node: str, taint: dict, present: bool = True) -> dict | None:
        """Add (or remove) one taint, matched on key and effect.

        Adding first tries one JSON-patch append (one round trip: the reconcile phase is on the clock); the API
        refuses it when the node has no taint list or already has that key and effect, and then the node is
        read and rewritten.
        """
        if present:
            body = {"key": taint["key"], "value": taint.get("value") or "", "effect": taint["effect"]}
            try:
                return self.request(
                    "PATCH", f"/api/v1/nodes/{node}", [{"op": "add", "path": "/spec/taints/-", "value": body}],
                    content_type=JSON_PATCH,
                )  # fmt: skip
            except ApiException as exc:
                if exc.status not in (409, 422):
                    raise

        def change(obj: dict):
            spec = obj.setdefault("spec", {})
            taints = list(spec.get("taints") or [])
            same = [t for t in taints if t.get("key") == taint["key"] and t.get("effect") == taint["effect"]]
            if present:
                if same and all((t.get("value") or "") == (taint.get("value") or "") for t in same):
                    return False
                taints = [t for t in taints if t not in same] + [
                    {"key": taint["key"], "value": taint.get("value") or "", "effect": taint["effect"]}
                ]
            else:
                if not same:
                    return False
                taints = [t for t in taints if t not in same]
            spec["taints"] = taints
            return True

        return self.update_node(node, change)

    # ---- pods --------------------------------------------------------------------------------------------
    def pods_path(self, namespace: str | None) -> str:
        return "/api/v1/pods" if namespace is None else f"/api/v1/namespaces/{namespace}/pods"

    def list_pods(self, namespace: str | None, **query) -> list[dict]:
        return self.get(self.pods_path(namespace), **query).get("items") or []

    def bind(self, namespace: str, name: str, node: str, uid: str | None = None) -> tuple[bool, str]:
        """The bind phase: a Binding for the pod (``uid`` guards against a re-created pod of the same name)."""
        meta: dict[str, Any] = {"name": name}
        if uid:
            meta["uid"] = uid
        body = {
            "apiVersion": "v1",
            "kind": "Binding",
            "metadata": meta,
            "target": {"apiVersion": "v1", "kind": "Node", "name": node},
        }
        try:
            self.request("POST", f"/api/v1/namespaces/{namespace}/pods/{name}/binding", body)
        except ApiException as exc:
            return False, f"binding refused: {describe(exc)}"
        return True, f"bound to {node}"

    def delete_pod(self, namespace: str, name: str, uid: str | None = None) -> dict | None:
        """Evict: delete the pod with grace period 0 (the kill of Fig. 3.36). Returns the deleted pod (the API
        answers with it), or None when it was gone already (or replaced by another pod of the same name)."""
        body: dict[str, Any] = {"apiVersion": "v1", "kind": "DeleteOptions", "gracePeriodSeconds": 0}
        if uid:
            body["preconditions"] = {"uid": uid}
        try:
            answer = self.request("DELETE", f"/api/v1/namespaces/{namespace}/pods/{name}", body)
        except ApiException as exc:
            if exc.status in (404, 409):
                return None
            raise
        return answer if isinstance(answer, dict) and answer.get("kind") == "Pod" else {}

    def create_pod(self, namespace: str, body: dict) -> dict:
        return self.request("POST", self.pods_path(namespace), body)

    def explain_pending(self, pod: dict, message: str) -> None:
        """Tell the pod why it stays pending, as kube-scheduler does: the PodScheduled condition and an Event."""
        meta = pod["metadata"]
        namespace, name = meta["namespace"], meta["name"]
        condition = {
            "type": "PodScheduled",
            "status": "False",
            "reason": "Unschedulable",
            "message": message,
            "lastTransitionTime": now_rfc3339(),
        }
        try:
            self.request(
                "PATCH",
                f"/api/v1/namespaces/{namespace}/pods/{name}/status",
                {"status": {"conditions": [condition]}},
                content_type=STRATEGIC_PATCH,
            )
        except ApiException as exc:
            if exc.status != 404:
                raise
        self.event(pod, "FailedScheduling", message, "Warning")

    def event(self, pod: dict, reason: str, message: str, kind: str = "Normal") -> None:
        meta = pod["metadata"]
        stamp = now_rfc3339()
        digest = hashlib.sha1(f"{meta.get('uid')}{reason}{message}{time.time()}".encode()).hexdigest()[:10]
        body = {
            "apiVersion": "v1",
            "kind": "Event",
            "metadata": {"name": f"{meta['name'][:200]}.{digest}", "namespace": meta["namespace"]},
            "involvedObject": {
                "apiVersion": "v1",
                "kind": "Pod",
                "name": meta["name"],
                "namespace": meta["namespace"],
                "uid": meta.get("uid"),
            },
            "reason": reason,
            "message": message[:1024],
            "type": kind,
            "source": {"component": RT_SCHEDULER_NAME},
            "reportingComponent": RT_SCHEDULER_NAME,
            "firstTimestamp": stamp,
            "lastTimestamp": stamp,
            "count": 1,
        }
        try:
            self.request("POST", f"/api/v1/namespaces/{meta['namespace']}/events", body)
        except ApiException as exc:
            if exc.status not in (404, 409):
                raise


def replacement_pod(pod: dict) -> dict:
    """A fresh, unbound copy of an evicted pod nobody owns: what its ReplicaSet would create (spec 03 5.4)."""
    meta = pod["metadata"]
    spec = copy.deepcopy(pod.get("spec") or {})
    spec.pop("nodeName", None)
    return {
        "apiVersion": "v1",
        "kind": "Pod",
        "metadata": {
            "name": meta["name"],
            "namespace": meta["namespace"],
            "labels": dict(meta.get("labels") or {}),
            "annotations": dict(meta.get("annotations") or {}),
        },
        "spec": spec,
    }


# ---- one client per cluster and process -------------------------------------------------------------------
_CLIENTS: dict[tuple[int, str], Kube] = {}
_LOCK = threading.Lock()


def kube_for(cluster: Cluster) -> Kube:
    """A cached :class:`Kube` for the cluster (rebuilt when its kubeconfig or context changes)."""
    digest = hashlib.sha256(f"{cluster.kube_context}\n{cluster.kubeconfig}".encode()).hexdigest()
    key = (cluster.pk, digest)
    with _LOCK:
        kube = _CLIENTS.get(key)
        if kube is None:
            for old in [k for k in _CLIENTS if k[0] == cluster.pk]:
                _CLIENTS.pop(old)
            kube = Kube(api_client_for(cluster), cluster.name)
            _CLIENTS[key] = kube
        return kube


def has_api(cluster: Cluster) -> bool:
    return bool(cluster.kubeconfig.strip())


def requests_of(pod: dict) -> tuple[float, float]:
    """The pod's CPU (cores) and memory (MiB) requests, summed over its containers."""
    from apps.kube.gateway import _cores, _mib

    cpu = mem = 0.0
    for c in (pod.get("spec") or {}).get("containers") or []:
        req = (c.get("resources") or {}).get("requests") or {}
        cpu += _cores(req.get("cpu")) or 0.0
        mem += _mib(req.get("memory")) or 0.0
    return cpu, mem


def parse_time(stamp: str | None) -> datetime | None:
    if not stamp:
        return None
    try:
        return datetime.fromisoformat(stamp.replace("Z", "+00:00"))
    except ValueError:
        return None


def names(items: Iterable[dict]) -> list[str]:
    return [i["metadata"]["name"] for i in items]
