"""``python manage.py heft4k_watch --cluster ID [--timeout S] [--threshold F] [--json]``: the node watcher.

Superseded by ``cluster_agent``, which runs the same remap trigger as a node handler (``heft4k-remap``) next to
the live pod state; kept for scripts and for ``--threshold``. Node status goes through the one writer
(:func:`apps.clusters.nodes.record_node_status`) either way.
"""

from __future__ import annotations

from typing import Any

from django.core.management.base import CommandError

from apps.clusters.models import Cluster
from apps.heft4k.watch import watch_nodes
from apps.kube import gateway
from continuum.commands import EngineCommand
from continuum.engine.core.errors import InputError


class Command(EngineCommand):
    help = (
        "Watch the Node objects of a cluster's Kubernetes API; when a node goes NotReady or disappears, mark it "
        "and remap (HEFT4K Algorithm 2) the latest pushed schedule of every application that had tasks on it."
    )

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("--cluster", type=int, required=True, help="cluster id")
        parser.add_argument("--timeout", type=float, default=None, help="stop after this many seconds (default: never)")
        parser.add_argument(
            "--threshold", type=float, default=None, help="lost rank share above which to remap totally (0-1)"
        )
        parser.add_argument("--retries", type=int, default=5, help="reconnects in a row before giving up")

    def run(self, **options: Any) -> dict:
        cluster = Cluster.objects.filter(pk=options["cluster"]).first()
        if cluster is None:
            raise InputError(f"cluster {options['cluster']} does not exist", "cluster")
        if options["timeout"] is not None and options["timeout"] <= 0:
            raise InputError(f"--timeout must be positive, not {options['timeout']!r}", "timeout")
        if options["threshold"] is not None and not 0.0 <= options["threshold"] <= 1.0:
            raise InputError(f"--threshold must be a fraction in [0, 1], not {options['threshold']!r}", "threshold")
        if options["retries"] < 0:
            raise InputError(f"--retries must not be negative, not {options['retries']!r}", "retries")
        try:
            report = watch_nodes(
                cluster, timeout=options["timeout"], threshold=options["threshold"], retries=options["retries"]
            )
        except gateway.KubeError as exc:
            raise CommandError(str(exc), returncode=1) from exc
        except KeyboardInterrupt:
            return {"cluster": cluster.pk, "interrupted": True}
        return report.to_dict()

    def summary(self, result: dict) -> str:
        if result.get("interrupted"):
            return f"cluster {result['cluster']}: watch interrupted"
        lines = [
            f"cluster {result['cluster']}: {result['events']} node events, {result['lists']} lists, "
            f"{result['reconnects']} reconnects"
        ]
        lines += [f"  node {c['node']}: {c['was']} -> {c['status']}" for c in result["changes"]]
        lines += [
            f"  remap of schedule {r['schedule']} without {', '.join(r['fail'])}: job {r['job']} {r['state']}"
            + (f" (remap {r['remap']})" if r["remap"] else "")
            for r in result["remaps"]
        ]
        return "\n".join(lines)
