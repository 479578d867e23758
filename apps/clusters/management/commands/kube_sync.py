"""``python manage.py kube_sync CLUSTER_ID [--json]``: read a cluster's nodes from its Kubernetes API now."""

from __future__ import annotations

from typing import Any

from django.core.management.base import CommandError

from apps.clusters import kube
from apps.clusters.models import Cluster
from apps.kube.gateway import KubeError
from continuum.commands import EngineCommand
from continuum.engine.core.errors import InputError


class Command(EngineCommand):
    help = "Sync a cluster's nodes (capacity, arch, Ready, taints, labels) from its Kubernetes API."

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("cluster", type=int, help="cluster id")

    def run(self, **options: Any) -> dict:
        cluster = Cluster.objects.filter(pk=options["cluster"]).first()
        if cluster is None:
            raise InputError(f"cluster {options['cluster']} does not exist", "cluster")
        try:
            counts = kube.sync_nodes(cluster)
        except KubeError as exc:
            raise CommandError(str(exc), returncode=1) from exc
        return {"cluster": cluster.pk, "name": cluster.name, **counts}

    def summary(self, result: dict) -> str:
        return (
            f"cluster {result['name']}: {result['nodes']} nodes in the API, {result['created']} created, "
            f"{result['updated']} updated, {result['unchanged']} unchanged, {result['gone']} gone (now NotReady)"
        )
