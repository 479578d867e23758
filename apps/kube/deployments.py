"""Deployments: create, or replace when their manifest changed (the manifest's hash in an annotation).

The manifests are the caller's domain data (plain dicts, e.g. ``apps.containers.kube.deployment_manifest``);
this module only talks to the API.
"""

from __future__ import annotations

import json
from typing import Any

from kubernetes import client
from kubernetes.client.exceptions import ApiException

from . import nodes, pods
from .connect import REQUEST_TIMEOUT, describe


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

    def existing(self, label_selector: str) -> dict[str, Any]:
        """The namespace's Deployments matching ``label_selector``, by name."""
        items = self.apps.list_namespaced_deployment(
            self.namespace, label_selector=label_selector, _request_timeout=REQUEST_TIMEOUT
        ).items
        return {d.metadata.name: d for d in items}

    def apply(self, body: dict[str, Any], current) -> tuple[bool, str]:
        """(ok, what happened): created, updated or unchanged, or why the API refused."""
        name = body["metadata"]["name"]
        if current is None:
            try:
                self.apps.create_namespaced_deployment(self.namespace, body, _request_timeout=REQUEST_TIMEOUT)
                return True, "created"
            except ApiException as exc:
                if exc.status != 409:
                    return False, f"Deployment {name} refused: {describe(exc)}"
                # Created meanwhile (a re-delivered job running twice): compare with what is there.
                current = self.apps.read_namespaced_deployment(name, self.namespace, _request_timeout=REQUEST_TIMEOUT)
        annotations = current.metadata.annotations or {}
        if annotations.get(self.hash_annotation) == body["metadata"]["annotations"][self.hash_annotation]:
            return True, "unchanged"
        replacement = json.loads(json.dumps(body))
        replacement["metadata"]["resourceVersion"] = current.metadata.resource_version
        try:
            self.apps.replace_namespaced_deployment(name, self.namespace, replacement, _request_timeout=REQUEST_TIMEOUT)
        except ApiException as exc:
            return False, f"Deployment {name} not updated: {describe(exc)}"
        return True, "updated"
