"""Deployments: create, or replace when their manifest changed (the manifest's hash in an annotation).

The manifests are the caller's domain data (plain dicts, e.g. ``apps.containers.kube.deployment_manifest``);
this module only talks to the API. :meth:`Deployments.apply_all` applies many at once, at most
``CONTINUUM_KUBE_PUSH_CONCURRENCY`` in flight (:mod:`apps.kube.parallel`). Every call is retried on transient
failures (:mod:`apps.kube.retry`) and is idempotent: Deployment names are the caller's deterministic names,
a create answered 409 (our own earlier attempt whose answer was lost, or a re-delivered job) is compared by
the manifest hash, and a replace answered 409 (the object changed since we read it, possibly by our own
retried replace) is read again and compared the same way, so a retry never makes a second Deployment.
"""

from __future__ import annotations

import json
from typing import Any

from kubernetes import client
from kubernetes.client.exceptions import ApiException

from . import nodes, parallel, pods
from .connect import API_ERRORS, by_label, call, describe, read_json

#: Replaces answered 409 (changed meanwhile) retried against a fresh read before giving up.
REPLACE_ATTEMPTS = 5


class Deployments:
    """The Deployments of one namespace, through one API client."""

    def __init__(self, api_client: client.ApiClient, namespace: str, hash_annotation: str) -> None:
        self.api_client = api_client
        self.namespace = namespace
        self.hash_annotation = hash_annotation
        self.apps = client.AppsV1Api(api_client)
        self.server = api_client.configuration.host

    def ensure_namespace(self) -> None:
        pods.ensure_namespace(self.api_client, self.namespace)

    def node_problems(self) -> dict[str, str | None]:
        return nodes.node_problems(self.api_client)

    def existing(self, label_selector: str) -> dict[str, dict[str, Any]]:
        """The namespace's Deployments matching ``label_selector``, by name, as the server's JSON
        (:func:`~apps.kube.connect.by_label`; only the hash annotation and the resourceVersion are read)."""
        return by_label(
            self.apps.list_namespaced_deployment,
            self.namespace,
            label_selector,
            what=f"list Deployments in namespace {self.namespace}",
            server=self.server,
        )

    def prepare(self, label_selector: str) -> tuple[dict[str, str | None], dict[str, Any]]:
        """Before a push, at once: the namespace made if missing, the nodes' problems
        (:func:`apps.kube.nodes.node_problems`) and the Deployments matching ``label_selector``."""
        _, problems, current = parallel.gather(
            self.ensure_namespace, self.node_problems, lambda: self.existing(label_selector)
        )
        return problems, current

    def _read(self, name: str) -> dict[str, Any]:
        return call(
            read_json,
            self.apps.read_namespaced_deployment,
            name,
            self.namespace,
            what=f"read Deployment {name}",
            server=self.server,
        )

    def _write(self, method: Any, *args: Any, what: str) -> None:
        """One create or replace, retried (:func:`~apps.kube.connect.call`); its answer is not used, so it is
        read raw and drained, not parsed into models."""
        pods.drain(call(method, *args, _preload_content=False, what=what, server=self.server))

    def _hash(self, current: dict[str, Any]) -> str | None:
        return ((current.get("metadata") or {}).get("annotations") or {}).get(self.hash_annotation)

    def apply(self, body: dict[str, Any], current: dict[str, Any] | None) -> tuple[bool, str]:
        """(ok, what happened): created, updated or unchanged, or why the API refused. ``current``: the
        Deployment's JSON as listed by :meth:`existing` (``None``: not there)."""
        name = body["metadata"]["name"]
        wanted = body["metadata"]["annotations"][self.hash_annotation]
        if current is None:
            try:
                self._write(
                    self.apps.create_namespaced_deployment, self.namespace, body, what=f"create Deployment {name}"
                )
                return True, "created"
            except ApiException as exc:
                if exc.status != 409:
                    return False, f"Deployment {name} refused: {describe(exc)}"
                # Created meanwhile (a re-delivered job, or our own create whose answer was lost and was
                # retried): compare with what is there.
                current = self._read(name)
        for _ in range(REPLACE_ATTEMPTS):
            if self._hash(current) == wanted:
                return True, "unchanged"
            replacement = json.loads(json.dumps(body))
            replacement["metadata"]["resourceVersion"] = current["metadata"]["resourceVersion"]
            try:
                self._write(
                    self.apps.replace_namespaced_deployment,
                    name,
                    self.namespace,
                    replacement,
                    what=f"replace Deployment {name}",
                )
                return True, "updated"
            except ApiException as exc:
                if exc.status != 409:
                    return False, f"Deployment {name} not updated: {describe(exc)}"
                # Changed since we read it: the Deployment controller's status writes bump the resourceVersion,
                # and so does a retried replace of ours the server had done. Read again: done if the hash is ours.
                current = self._read(name)
                if self._hash(current) == wanted:
                    return True, "updated"
        return False, f"Deployment {name} not updated: it kept changing while we wrote it"

    def apply_all(
        self,
        work: list[tuple[dict[str, Any], Any]],
        progress=None,
        *,
        workers: int | None = None,
    ) -> tuple[list[tuple[bool, str]], str | None]:
        """:meth:`apply` every ``(body, current)`` with at most ``workers`` (``CONTINUUM_KUBE_PUSH_CONCURRENCY``)
        in flight, started in the given order; returns the results in that order and, when the API went away,
        why (the bodies not applied yet then fail with that reason). ``progress(done)`` runs in this thread."""
        return parallel.run_bounded(
            work,
            lambda item: self.apply(item[0], item[1]),
            skipped=lambda reason: (False, reason),
            fatal=API_ERRORS,
            describe=lambda exc: describe(exc, self.server),
            workers=workers,
            progress=progress,
        )
