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

    def handle(self, *args, **options) -> None:
        cluster = Cluster.objects.filter(pk=options["cluster"]).first()
        if cluster is None:
            raise CommandError(f"cluster {options['cluster']} does not exist")
        if not cluster.kubeconfig.strip():
            raise CommandError(f"cluster {cluster.name!r} has no kubeconfig: it is a model-only cluster")
        logging.getLogger("continuum.rt_scheduler").setLevel(logging.INFO)
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
