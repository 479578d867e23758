"""Objects as JSON through the official client: namespaces, CustomResourceDefinitions and custom objects
(with their status subresource), pods (Bindings, evictions, replacements), scheduler explanations (the
``PodScheduled`` condition and Events) and node taints.

Every call is a typed method of the official client (``CoreV1Api``, ``CustomObjectsApi``,
``ApiextensionsV1Api``) answered as the server's JSON (:func:`apps.kube.connect.read_json`): custom objects,
Bindings and Status answers need no model classes, and large pod lists parse quickly. Every call goes through
:func:`apps.kube.connect.call` (:mod:`apps.kube.retry`): transient failures (504/503, reset or refused
connections) are retried with backoff until ``CONTINUUM_KUBE_RETRY_DEADLINE_S``, then
:class:`~apps.kube.retry.GaveUp` names the call. Each call is safe to repeat, or says why not
(``idempotent=False``: then it is repeated only when the request surely never reached the server). Used by RT-Kube
(thesis 3.4, Fig. 3.32; spec 03 sections 3, 4.4, 5.4), whose CRD manifests and RealTime/Monitoring documents
are its own domain data, passed in as plain dicts.
"""

from __future__ import annotations

import copy
import hashlib
import time
from collections.abc import Callable, Mapping
from datetime import UTC, datetime
from typing import Any

from kubernetes import client
from kubernetes.client.exceptions import ApiException

from continuum.engine.core.taints import Taint

from . import nodes
from .connect import KubeError, call, describe, read_json

# The official client imports its API and model classes on first use (a module __getattr__ and import_module):
# resolved here, when the gateway is imported (a worker's start), so that no eviction, binding or taint pays that
# import on the clock, one thread at a time under the import lock (hundreds of ms on a busy machine).
EAGER = (client.CoreV1Api, client.CustomObjectsApi, client.VersionApi, client.ApiextensionsV1Api,
         client.V1DeleteOptions, client.V1Preconditions, client.V1Binding, client.V1ObjectMeta,
         client.V1ObjectReference)  # fmt: skip
MERGE_PATCH = "application/merge-patch+json"
STRATEGIC_PATCH = "application/strategic-merge-patch+json"


def now_rfc3339() -> str:
    return datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def pod_event(
    namespace: str,
    name: str,
    reason: str,
    message: str,
    component: str,
    *,
    kind: str = "Normal",
    uid: str | None = None,
) -> dict[str, Any]:
    """A core/v1 Event about pod ``namespace/name``, as kube-scheduler writes them (``Scheduled``,
    ``FailedScheduling``): what ``kubectl describe pod`` and the live state show."""
    stamp = now_rfc3339()
    digest = hashlib.sha1(f"{namespace}/{name}/{uid}/{reason}/{message}/{time.time()}".encode()).hexdigest()[:10]
    return {
        "apiVersion": "v1",
        "kind": "Event",
        "metadata": {"name": f"{name[:200]}.{digest}", "namespace": namespace},
        "involvedObject": {"apiVersion": "v1", "kind": "Pod", "name": name, "namespace": namespace, "uid": uid},
        "reason": reason,
        "message": message[:1024],
        "type": kind,
        "source": {"component": component},
        "reportingComponent": component,
        "firstTimestamp": stamp,
        "lastTimestamp": stamp,
        "count": 1,
    }


class Kube:
    """JSON access to one cluster's API server (``component``: who writes the Events, e.g. the RT scheduler)."""

    def __init__(self, api_client: client.ApiClient, name: str = "", component: str = "continuum") -> None:
        self.api_client = api_client
        self.name = name
        self.component = component
        self.server = api_client.configuration.host
        self.core = client.CoreV1Api(api_client)
        self.custom = client.CustomObjectsApi(api_client)
        self.extensions = client.ApiextensionsV1Api(api_client)

    def _json(self, fn, *args, what: str, idempotent: bool = True, **kwargs):
        """``read_json(fn, *args, **kwargs)`` retried on transient failures (see the module docstring)."""
        return call(read_json, fn, *args, what=what, server=self.server, idempotent=idempotent, **kwargs)

    def version(self, retried: bool = True) -> dict:
        """The API server's version: the cheapest read there is, used to open (warm) a connection. ``retried``
        False: one attempt (warming must not hold a thread for the retry deadline when the API is down)."""
        get_code = client.VersionApi(self.api_client).get_code
        if not retried:
            return read_json(get_code) or {}
        return self._json(get_code, what="read the API version") or {}

    # ---- namespaces and CRDs ---------------------------------------------------------------------------
    def ensure_namespace(self, namespace: str) -> None:
        try:
            self._json(self.core.read_namespace, namespace, what=f"read namespace {namespace}")
            return
        except ApiException as exc:
            if exc.status != 404:
                raise
        body = {"apiVersion": "v1", "kind": "Namespace", "metadata": {"name": namespace}}
        try:
            self._json(self.core.create_namespace, body, what=f"create namespace {namespace}")
        except ApiException as exc:
            if exc.status != 409:
                raise

    def install_crds(self, manifests: list[dict], wait: float = 20.0) -> list[str]:
        """Create or update the CRDs and wait until they are Established; returns what changed."""
        changed = []
        for crd in manifests:
            name = crd["metadata"]["name"]
            try:
                current = self._json(self.extensions.read_custom_resource_definition, name, what=f"read CRD {name}")
            except ApiException as exc:
                if exc.status != 404:
                    raise
                create = self.extensions.create_custom_resource_definition
                self._json(create, crd, what=f"create CRD {name}", idempotent=False)
                changed.append(f"created {name}")
                continue
            if (
                current.get("spec", {}).get("versions") != crd["spec"]["versions"]
                or current["spec"].get("names", {}).get("shortNames") != crd["spec"]["names"]["shortNames"]
            ):
                body = copy.deepcopy(crd)
                body["metadata"]["resourceVersion"] = current["metadata"]["resourceVersion"]
                self._json(self.extensions.replace_custom_resource_definition, name, body, what=f"replace CRD {name}")
                changed.append(f"updated {name}")
        deadline = time.monotonic() + wait
        for crd in manifests:
            name = crd["metadata"]["name"]
            while True:
                answer = self._json(self.extensions.read_custom_resource_definition, name, what=f"read CRD {name}")
                conditions = (answer.get("status") or {}).get("conditions") or []
                if any(c.get("type") == "Established" and c.get("status") == "True" for c in conditions):
                    break
                if time.monotonic() > deadline:
                    raise KubeError(f"CRD {name} is not Established after {wait:g} s")
                time.sleep(0.1)
        return changed

    # ---- custom objects --------------------------------------------------------------------------------
    def list_objects(self, group: str, version: str, plural: str, namespace: str | None) -> list[dict]:
        if namespace is None:
            answer = self._json(self.custom.list_cluster_custom_object, group, version, plural, what=f"list {plural}")
        else:
            answer = self._json(
                self.custom.list_namespaced_custom_object, group, version, namespace, plural, what=f"list {plural}"
            )
        return (answer or {}).get("items") or []

    def get_object(self, group: str, version: str, plural: str, namespace: str, name: str) -> dict | None:
        try:
            return self._json(
                self.custom.get_namespaced_custom_object, group, version, namespace, plural, name,
                what=f"read {plural}/{name}",
            )  # fmt: skip
        except ApiException as exc:
            if exc.status == 404:
                return None
            raise

    def put_object(self, group: str, version: str, plural: str, obj: dict) -> dict:
        """Create ``obj``, or replace the existing object's spec (keeping its status); returns the stored object."""
        namespace, name = obj["metadata"]["namespace"], obj["metadata"]["name"]
        for _ in range(5):
            current = self.get_object(group, version, plural, namespace, name)
            if current is None:
                try:
                    # A retried create the server had done answers 409: replaced below, the same object.
                    return self._json(
                        self.custom.create_namespaced_custom_object, group, version, namespace, plural, obj,
                        what=f"create {plural}/{name}",
                    )  # fmt: skip
                except ApiException as exc:
                    if exc.status != 409:
                        raise
                    continue  # created meanwhile: replace it
            body = copy.deepcopy(obj)
            body["metadata"] = {**current["metadata"], **obj["metadata"]}
            body["metadata"]["resourceVersion"] = current["metadata"]["resourceVersion"]
            try:
                return self._json(
                    self.custom.replace_namespaced_custom_object, group, version, namespace, plural, name, body,
                    what=f"replace {plural}/{name}",
                )  # fmt: skip
            except ApiException as exc:
                if exc.status != 409:
                    raise
        raise KubeError(f"{plural}/{name}: the object kept changing while we wrote it")

    def delete_object(self, group: str, version: str, plural: str, namespace: str, name: str) -> bool:
        try:
            self._json(
                self.custom.delete_namespaced_custom_object, group, version, namespace, plural, name,
                what=f"delete {plural}/{name}",
            )  # fmt: skip
            return True
        except ApiException as exc:
            if exc.status == 404:
                return False
            raise

    def patch_status(self, group: str, version: str, plural: str, namespace: str, name: str, status: dict) -> None:
        try:
            self._json(
                self.custom.patch_namespaced_custom_object_status,
                group,
                version,
                namespace,
                plural,
                name,
                {"status": status},
                _content_type=MERGE_PATCH,
                what=f"write the status of {plural}/{name}",
            )
        except ApiException as exc:
            if exc.status != 404:  # deleted meanwhile: nothing to annotate
                raise

    # ---- nodes -------------------------------------------------------------------------------------------
    def list_nodes(self) -> list[dict]:
        return (self._json(self.core.list_node, what="list nodes") or {}).get("items") or []

    def update_node(self, name: str, change: Callable[[dict], Any]) -> dict | None:
        """See :func:`apps.kube.nodes.update_node`."""
        return nodes.update_node(self.api_client, name, change)

    def set_taint(self, node: str, taint: Taint | Mapping[str, Any], present: bool = True) -> dict | None:
        """See :func:`apps.kube.nodes.set_taint`."""
        return nodes.set_taint(self.api_client, node, taint, present)

    # ---- pods --------------------------------------------------------------------------------------------
    def list_pods(self, namespace: str | None, **query) -> list[dict]:
        if namespace is None:
            answer = self._json(self.core.list_pod_for_all_namespaces, what="list pods", **query)
        else:
            answer = self._json(self.core.list_namespaced_pod, namespace, what=f"list pods in {namespace}", **query)
        return (answer or {}).get("items") or []

    def bind(self, namespace: str, name: str, node: str, uid: str | None = None) -> tuple[bool, str]:
        """The bind phase: a Binding for the pod (``uid`` guards against a re-created pod of the same name)."""
        body = client.V1Binding(
            api_version="v1",
            kind="Binding",
            metadata=client.V1ObjectMeta(name=name, uid=uid or None),
            target=client.V1ObjectReference(api_version="v1", kind="Node", name=node),
        )
        try:
            what = f"bind pod {namespace}/{name} to {node}"
            self._json(self.core.create_namespaced_pod_binding, name, namespace, body, what=what)
        except ApiException as exc:
            # A retried binding the server had done (its answer lost) answers 409: done if bound there.
            if exc.status == 409 and self._bound_to(namespace, name, uid) == node:
                return True, f"bound to {node}"
            return False, f"binding refused: {describe(exc)}"
        return True, f"bound to {node}"

    def _bound_to(self, namespace: str, name: str, uid: str | None) -> str | None:
        """The node pod ``namespace/name`` (of ``uid``, when given) is bound to; ``None``: not bound, or gone."""
        try:
            pod = self._json(self.core.read_namespaced_pod, name, namespace, what=f"read pod {namespace}/{name}")
        except ApiException as exc:
            if exc.status == 404:
                return None
            raise
        if uid and pod["metadata"].get("uid") != uid:
            return None
        return (pod.get("spec") or {}).get("nodeName")

    def delete_pod(self, namespace: str, name: str, uid: str | None = None) -> dict | None:
        """Evict: delete the pod with grace period 0 (the kill of Fig. 3.36). Returns the deleted pod (the API
        answers with it), or None when it was gone already (or replaced by another pod of the same name)."""
        body = client.V1DeleteOptions(
            api_version="v1",
            kind="DeleteOptions",
            grace_period_seconds=0,
            preconditions=client.V1Preconditions(uid=uid) if uid else None,
        )
        try:
            # Idempotent: a retried deletion the server had done answers 404 (or 409 for the uid): "gone already".
            answer = self._json(
                self.core.delete_namespaced_pod, name, namespace, body=body, what=f"evict pod {namespace}/{name}"
            )
        except ApiException as exc:
            if exc.status in (404, 409):
                return None
            raise
        return answer if isinstance(answer, dict) and answer.get("kind") == "Pod" else {}

    def create_pod(self, namespace: str, body: dict) -> dict:
        # Not idempotent (a repeated create answers 409 and the caller cannot tell whose pod that is): repeated
        # only when the request never reached the server.
        name = (body.get("metadata") or {}).get("name", "")
        return self._json(
            self.core.create_namespaced_pod, namespace, body, what=f"create pod {namespace}/{name}", idempotent=False
        )

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
            self._json(
                self.core.patch_namespaced_pod_status,
                name,
                namespace,
                {"status": {"conditions": [condition]}},
                _content_type=STRATEGIC_PATCH,
                what=f"explain pod {namespace}/{name}",
            )
        except ApiException as exc:
            if exc.status != 404:
                raise
        self.event(pod, "FailedScheduling", message, "Warning")

    def event(self, pod: dict, reason: str, message: str, kind: str = "Normal") -> None:
        meta = pod["metadata"]
        body = pod_event(
            meta["namespace"], meta["name"], reason, message, self.component, kind=kind, uid=meta.get("uid")
        )
        try:
            # Idempotent: the Event's name is unique, so a retried create the server had done answers 409.
            self._json(
                self.core.create_namespaced_event, meta["namespace"], body,
                what=f"record event {reason} of pod {meta['namespace']}/{meta['name']}",
            )  # fmt: skip
        except ApiException as exc:
            if exc.status not in (404, 409):
                raise
