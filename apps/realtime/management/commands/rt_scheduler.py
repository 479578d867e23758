"""``python manage.py rt_scheduler --cluster ID``: RT-Kube's secondary scheduler as a long-running process.

Watches pods with ``schedulerName: RT-scheduler`` in the cluster's Kubernetes API and binds them (thesis 3.4,
Fig. 3.34); mirrors RealTime/Monitoring objects and lifts expired node taints. Stops cleanly on SIGTERM or
Ctrl-C; a failing cycle is logged and retried, never fatal.
"""

from __future__ import annotations

import logging
import signal
import threading

from django.core.management.base import BaseCommand, CommandError

from apps.clusters.models import Cluster
from apps.realtime.scheduler import RTScheduler
from continuum.metrics import port_from_env, serve


class Command(BaseCommand):
    help = "Run RT-Kube's secondary real-time scheduler for one cluster (binds pods with schedulerName RT-scheduler)."

    def add_arguments(self, parser) -> None:
        parser.add_argument("--cluster", type=int, required=True, help="id of the cluster (it needs a kubeconfig)")
        parser.add_argument("--namespace", help="namespace to serve (default: the cluster's); '*' for all")
        parser.add_argument("--period", type=float, default=1.0, help="seconds between cycles without events")
        parser.add_argument("--sync-period", type=float, default=5.0, help="seconds between two mirrors")
        parser.add_argument("--no-watch", action="store_true", help="poll only (no watch connections)")
        parser.add_argument("--once", action="store_true", help="run one cycle and exit")
        parser.add_argument("--max-seconds", type=float, help="stop after this many seconds")
        parser.add_argument(
            "--metrics-port", type=int, help="serve /metrics on this port (env CONTINUUM_METRICS_PORT; 0: any free)"
        )

    def handle(self, *args, **options) -> None:
        cluster = Cluster.objects.filter(pk=options["cluster"]).first()
        if cluster is None:
            raise CommandError(f"cluster {options['cluster']} does not exist")
        if not cluster.kubeconfig.strip():
            raise CommandError(f"cluster {cluster.name!r} has no kubeconfig: it is a model-only cluster")
        logging.getLogger("continuum.rt_scheduler").setLevel(logging.INFO)
        self.serve_metrics(options.get("metrics_port"))
        stop = threading.Event()
        for sig in (signal.SIGTERM, signal.SIGINT):
            signal.signal(sig, lambda *_: stop.set())
        if options.get("max_seconds"):
            timer = threading.Timer(options["max_seconds"], stop.set)
            timer.daemon = True
            timer.start()

        def report(result) -> None:
            for key, node in result.bound:
                self.stdout.write(f"bound {key} -> {node}")
            for key, why in result.pending.items():
                self.stdout.write(f"pending {key}: {why}")
            for key, why in result.failed.items():
                self.stderr.write(f"failed {key}: {why}")
            self.stdout.flush()

        scheduler = RTScheduler(
            cluster.pk,
            namespace=options.get("namespace"),
            period=options["period"],
            sync_period=options["sync_period"],
            watch=not options["no_watch"] and not options["once"],
            on_cycle=report,
        )
        self.stdout.write(f"RT scheduler for cluster {cluster.name!r} ({cluster.pk}) started")
        self.stdout.flush()
        cycles = scheduler.run(stop, max_cycles=1 if options["once"] else None)
        self.stdout.write(f"RT scheduler stopped after {cycles} cycles ({scheduler.errors} failed)")

    def serve_metrics(self, port: int | None) -> None:
        try:
            port = port if port is not None else port_from_env()
        except ValueError as exc:
            raise CommandError(str(exc)) from exc
        if port is None:
            return
        if not 0 <= port <= 65535:
            raise CommandError(f"--metrics-port must be a port number (0-65535), not {port}")
        _server, bound = serve(port)
        self.stdout.write(f"metrics on port {bound}")
        self.stdout.flush()
