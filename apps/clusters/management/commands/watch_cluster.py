"""``python manage.py watch_cluster CLUSTER [--namespace NS ...] [--max-seconds S] [--json]``: live pod state.

An alias of ``cluster_agent --cluster ID`` for one cluster in the foreground (the same watches and handlers),
kept for scripts; ``--namespace`` widens what it follows, but pods outside the cluster's own namespace only
reach handlers that join by uid (see :func:`apps.clusters.live.register_pod_handler`).

Follows the pods and pod Events of a cluster's Kubernetes API and stores each pod's phase, node and newest
event on the rows of the apps that own it (assignments, container deployments, RT pods; see
:mod:`apps.clusters.live`). Long-running: it stops on Ctrl-C, or after ``--max-seconds``.
"""

from __future__ import annotations

from typing import Any

from django.core.management.base import CommandError

from apps.clusters.live import watch_cluster
from apps.clusters.models import Cluster
from apps.clusters.nodes import node_handlers
from apps.kube import gateway
from continuum.commands import EngineCommand
from continuum.engine.core.errors import InputError


def find_cluster(ref: str) -> Cluster:
    """The cluster with id ``ref``, else the one named ``ref`` (refused when several fleets have one)."""
    if ref.isdigit():
        cluster = Cluster.objects.filter(pk=int(ref)).first()
        if cluster is not None:
            return cluster
    named = list(Cluster.objects.filter(name=ref)[:2])
    if not named:
        raise InputError(f"cluster {ref!r} does not exist", "cluster")
    if len(named) > 1:
        raise InputError(f"several fleets have a cluster named {ref!r}: give its id", "cluster")
    return named[0]


class Command(EngineCommand):
    help = (
        "Watch a cluster's pods and their events and store each pod's phase, node and newest event on the "
        "schedule assignments, container deployments and RT pods it belongs to; keep its nodes' Ready status."
    )

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("cluster", help="id or name of the cluster (it needs a kubeconfig)")
        parser.add_argument(
            "--namespace",
            action="append",
            default=None,
            help="namespace to watch (repeatable; default: the cluster's); '*' for all",
        )
        parser.add_argument(
            "--max-seconds", "--timeout", dest="max_seconds", type=float, default=None, help="stop after this long"
        )
        parser.add_argument("--retries", type=int, default=5, help="reconnects in a row before giving up")

    def run(self, **options: Any) -> dict:
        cluster = find_cluster(str(options["cluster"]))
        if not cluster.kubeconfig.strip():
            raise InputError(f"cluster {cluster.name!r} has no kubeconfig: it is a model-only cluster", "cluster")
        if options["max_seconds"] is not None and options["max_seconds"] <= 0:
            raise InputError(f"--max-seconds must be positive, not {options['max_seconds']!r}", "max_seconds")
        if options["retries"] < 0:
            raise InputError(f"--retries must not be negative, not {options['retries']!r}", "retries")
        namespaces = options["namespace"] or [cluster.namespace]
        scope = None if "*" in namespaces else namespaces
        try:
            return watch_cluster(
                cluster,
                scope,
                timeout=options["max_seconds"],
                retries=options["retries"],
                node_handlers=node_handlers(),
            )
        except gateway.KubeError as exc:
            raise CommandError(str(exc), returncode=1) from exc
        except KeyboardInterrupt:
            return {"cluster": cluster.pk, "interrupted": True}

    def summary(self, result: dict) -> str:
        if result.get("interrupted"):
            return f"cluster {result['cluster']}: watch interrupted"
        updated = ", ".join(f"{k} {v}" for k, v in result["updated"].items()) or "none"
        return (
            f"cluster {result['cluster']} ({', '.join(result['namespaces'])}): {result['pod_events']} pod events, "
            f"{result['events']} pod Events, {result['pods']} pods; rows updated: {updated}; "
            f"{result['node_events']} node events, {result['nodes_updated']} node statuses changed; "
            f"{result['reconnects']} reconnects"
        )
