"""``python manage.py cluster_agent [--cluster ID ...] [--max-seconds S] [--json]``: the one agent of a cluster.

One process per deployment follows each registered cluster's Nodes, Pods and pod Events once (shared watches,
:func:`apps.clusters.live.watch_cluster`) and hands every change to the apps' registered handlers: live pod
state (schedules, ROS placements, RT-Kube), node status by one rule (:mod:`apps.clusters.nodes`) and HEFT4K's
remap trigger. Without ``--cluster`` it serves every cluster with a kubeconfig (one thread each; clusters
registered later are picked up every ``--rescan`` seconds). ``--leader-elect`` runs it as one of several
replicas: only the holder of the ``continuum-cluster-agent`` Lease works (see :mod:`apps.kube.leader`).

``watch_cluster`` and ``heft4k_watch`` remain as aliases of parts of it (README, Commands).
"""

from __future__ import annotations

import logging
import signal
import threading
import time
from typing import Any

from django.db import close_old_connections

from apps.clusters.live import pod_handlers, watch_cluster
from apps.clusters.models import Cluster
from apps.clusters.nodes import node_handlers
from apps.kube import gateway
from continuum.commands import EngineCommand
from continuum.engine.core.errors import InputError
from continuum.metrics import port_from_env, serve

log = logging.getLogger("continuum.cluster_agent")


def live_clusters(ids: list[int] | None) -> list[Cluster]:
    rows = Cluster.objects.order_by("pk")
    if ids:
        rows = rows.filter(pk__in=ids)
    return [c for c in rows if str(c.kubeconfig).strip()]


def serve_cluster(cluster: Cluster, stop: threading.Event, retries: int | None) -> dict:
    """Follow one cluster until ``stop``; a lost API is retried (back-off) for ever, never fatal to the others."""
    report: dict[str, Any] = {"cluster": cluster.pk, "errors": 0}
    while not stop.is_set():
        try:
            result = watch_cluster(
                cluster, [cluster.namespace], stop=stop, retries=retries, node_handlers=node_handlers()
            )
            report.update(result)
        except Exception as exc:  # one cluster's failure must not stop the agent
            report["errors"] += 1
            report["error"] = str(exc)
            log.warning("cluster agent: cluster %s: %s; again in 5 s", cluster.pk, exc)
            stop.wait(5)
        finally:
            close_old_connections()
    return report


class Command(EngineCommand):
    help = (
        "The cluster agent: follow each cluster's Nodes, Pods and Events once and hand the changes to the apps "
        "(live pod state, node status with one rule, HEFT4K's remap trigger)."
    )

    def add_arguments(self, parser) -> None:
        super().add_arguments(parser)
        parser.add_argument("--cluster", type=int, action="append", help="cluster id (repeatable; default: all)")
        parser.add_argument("--max-seconds", type=float, default=None, help="stop after this long")
        parser.add_argument("--rescan", type=float, default=30.0, help="seconds between looks for new clusters")
        parser.add_argument("--retries", type=int, default=None, help="reconnects in a row before a cluster's "
                            "watch restarts (default: never gives up)")  # fmt: skip
        parser.add_argument("--metrics-port", type=int, default=None, help="serve /metrics on this port "
                            "(env CONTINUUM_METRICS_PORT; 0: any free)")  # fmt: skip
        parser.add_argument("--leader-elect", action="store_true", help="run only while holding the Lease")
        parser.add_argument("--lease-namespace", default=None, help="namespace of the Lease (default: each "
                            "cluster's namespace)")  # fmt: skip

    def run(self, **options: Any) -> dict:
        if options["max_seconds"] is not None and options["max_seconds"] <= 0:
            raise InputError(f"--max-seconds must be positive, not {options['max_seconds']!r}", "max_seconds")
        if options["rescan"] <= 0:
            raise InputError(f"--rescan must be positive, not {options['rescan']!r}", "rescan")
        ids = options["cluster"]
        for pk in ids or []:
            cluster = Cluster.objects.filter(pk=pk).first()
            if cluster is None:
                raise InputError(f"cluster {pk} does not exist", "cluster")
            if not str(cluster.kubeconfig).strip():
                raise InputError(f"cluster {cluster.name!r} has no kubeconfig: it is a model-only cluster", "cluster")
        try:
            port = options["metrics_port"] if options["metrics_port"] is not None else port_from_env()
        except ValueError as exc:
            raise InputError(str(exc), "metrics_port") from exc
        if port is not None:
            if not 0 <= port <= 65535:
                raise InputError(f"--metrics-port must be a port number (0-65535), not {port}", "metrics_port")
            _server, bound = serve(port)
            self.stderr.write(f"metrics on port {bound}")
        stop = threading.Event()
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGTERM, signal.SIGINT):
                signal.signal(sig, lambda *_: stop.set())
        deadline = None if options["max_seconds"] is None else time.monotonic() + options["max_seconds"]
        return self.supervise(ids, stop, deadline, options)

    def supervise(self, ids: list[int] | None, stop: threading.Event, deadline: float | None, options) -> dict:
        """One thread per cluster (each behind its Lease with --leader-elect), new clusters picked up."""
        from apps.clusters.leader import elected

        threads: dict[int, threading.Thread] = {}
        reports: dict[int, dict] = {}

        def one(cluster: Cluster) -> None:
            def work(lost: threading.Event) -> None:
                reports[cluster.pk] = serve_cluster(cluster, lost, options["retries"])

            try:
                if options["leader_elect"]:
                    elected(cluster, "continuum-cluster-agent", work, stop, options["lease_namespace"])
                else:
                    work(stop)
            except gateway.KubeError as exc:
                reports[cluster.pk] = {"cluster": cluster.pk, "error": str(exc)}
            finally:
                close_old_connections()

        while not stop.is_set():
            for cluster in live_clusters(ids):
                if cluster.pk not in threads:
                    log.info("cluster agent: serving cluster %s (%s)", cluster.pk, cluster.name)
                    threads[cluster.pk] = threading.Thread(target=one, args=(cluster,), daemon=True,
                                                           name=f"agent-{cluster.pk}")  # fmt: skip
                    threads[cluster.pk].start()
            close_old_connections()
            left = options["rescan"] if deadline is None else min(options["rescan"], deadline - time.monotonic())
            if left <= 0 or stop.wait(left):
                break
        stop.set()
        for thread in threads.values():
            thread.join(timeout=60)
        return {"clusters": [reports.get(pk, {"cluster": pk}) for pk in sorted(threads)],
                "handlers": sorted(pod_handlers()) + sorted(node_handlers())}  # fmt: skip

    def summary(self, result: dict) -> str:
        lines = [f"cluster agent: {len(result['clusters'])} clusters; handlers {', '.join(result['handlers'])}"]
        for r in result["clusters"]:
            if "pod_events" in r:
                lines.append(
                    f"  cluster {r['cluster']}: {r['pod_events']} pod events, {r['events']} pod Events, "
                    f"{r['node_events']} node events, {r['nodes_updated']} node statuses changed, "
                    f"{r.get('foreign_pods', 0)} pods outside its namespace ignored"
                )
            else:
                lines.append(f"  cluster {r['cluster']}: {r.get('error', 'not started')}")
        return "\n".join(lines)
