"""The Kubernetes gateway: the one place Continuum talks to a Kubernetes API (the official client only).

One import for callers (``from apps.kube import gateway``); the parts live in small modules:

- :mod:`apps.kube.connect` -- API clients from a validated kubeconfig, the timeout and retry of each call
  (:mod:`apps.kube.retry`), :class:`KubeError` and the one-line descriptions of failures;
- :mod:`apps.kube.nodes` -- node states, capacities, architecture and taints as plain data; taint writes;
- :mod:`apps.kube.pods` -- a schedule's pods and their Bindings (engine assignments in, Outcomes out);
- :mod:`apps.kube.deployments` -- Deployments applied idempotently (manifest hash);
- :mod:`apps.kube.resources` -- CRDs, custom objects and their status, evictions, Events, pod conditions;
- :mod:`apps.kube.watch` -- the one watch loop (resume, 410 Gone, backoff);
- :mod:`apps.kube.podstate` -- a pod's live state (phase, node, latest event) from the watched JSON.

It takes and returns engine types and plain data, never another app's rows: the app that owns a stored
cluster builds the client from its kubeconfig (``apps.clusters.kube.api_client_for``) and records what
the gateway reports. Calls happen in jobs, commands and long-running processes, never in a web request.
"""

from __future__ import annotations

from .connect import (
    API_ERRORS,
    KUBE_ERRORS,
    REQUEST_TIMEOUT,
    KubeError,
    Progress,
    api_client,
    call,
    configuration_for,
    describe,
    problem,
    read_json,
    server_policy,
    target,
)
from .deployments import Deployments
from .nodes import (
    NOT_READY,
    READY,
    UNKNOWN,
    allocatable,
    cores,
    list_nodes,
    list_nodes_with_version,
    mib,
    name_of,
    node_fields,
    node_problems,
    node_status,
    node_taints,
    ready_nodes,
    set_taint,
    taints_of,
    update_node,
)
from .pods import (
    MANAGED_BY,
    PREFIX,
    Outcome,
    PodSet,
    Pusher,
    dns_part,
    ensure_namespace,
    label_value,
    pod_manifest,
    pod_name,
    push,
)
from .podstate import PodEvent, PodState, event_of, pod_state
from .resources import Kube
from .watch import WATCH_SECONDS, Watches, WatchStats, follow
from .watch import custom_objects as watch_custom_objects
from .watch import events as watch_events
from .watch import nodes as watch_nodes
from .watch import pods as watch_pods

__all__ = [
    "API_ERRORS",
    "KUBE_ERRORS",
    "MANAGED_BY",
    "NOT_READY",
    "PREFIX",
    "READY",
    "REQUEST_TIMEOUT",
    "UNKNOWN",
    "WATCH_SECONDS",
    "Deployments",
    "Kube",
    "KubeError",
    "Outcome",
    "PodEvent",
    "PodSet",
    "PodState",
    "Progress",
    "Pusher",
    "WatchStats",
    "Watches",
    "allocatable",
    "api_client",
    "call",
    "configuration_for",
    "cores",
    "describe",
    "dns_part",
    "ensure_namespace",
    "event_of",
    "follow",
    "label_value",
    "list_nodes",
    "list_nodes_with_version",
    "mib",
    "name_of",
    "node_fields",
    "node_problems",
    "node_status",
    "node_taints",
    "pod_manifest",
    "pod_name",
    "pod_state",
    "problem",
    "push",
    "read_json",
    "ready_nodes",
    "server_policy",
    "set_taint",
    "taints_of",
    "target",
    "update_node",
    "watch_custom_objects",
    "watch_events",
    "watch_nodes",
    "watch_pods",
]
