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

from apps.clusters.leader import elector
from apps.clusters.models import Cluster
from apps.kube.leader import Timing
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
        parser.add_argument("--leader-elect", action="store_true",
                            help="one of several replicas: schedule only while holding the Lease")  # fmt: skip
        parser.add_argument(
            "--lease-name", default="continuum-rt-scheduler", help="the Lease (in the cluster's namespace)"
        )
        parser.add_argument("--lease-duration", type=float, default=15.0, help="seconds (client-go's default 15)")
        parser.add_argument("--renew-deadline", type=float, default=10.0, help="seconds (10)")
        parser.add_argument("--retry-period", type=float, default=2.0, help="seconds (2)")
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

        def make() -> RTScheduler:
            return RTScheduler(
                cluster.pk,
                namespace=options.get("namespace"),
                period=options["period"],
                sync_period=options["sync_period"],
                watch=not options["no_watch"] and not options["once"],
                on_cycle=report,
            )

        if options["leader_elect"]:
            try:
                timing = Timing(options["lease_duration"], options["renew_deadline"], options["retry_period"])
            except ValueError as exc:
                raise CommandError(str(exc)) from exc
            runs: list[RTScheduler] = []

            def lead(lost: threading.Event) -> None:
                # A fresh scheduler each term: nothing assumed by an earlier term outlives the Lease.
                runs.append(make())
                self.stdout.write(f"leading (Lease {options['lease_name']})")
                self.stdout.flush()
                runs[-1].run(lost, max_cycles=1 if options["once"] else None)
                self.stdout.write("no longer leading")
                self.stdout.flush()

            self.stdout.write(f"RT scheduler for cluster {cluster.name!r} ({cluster.pk}) started, electing")
            self.stdout.flush()
            elector(cluster, options["lease_name"], timing=timing).run(lead, stop)
            cycles, errors = sum(r.cycles for r in runs), sum(r.errors for r in runs)
            self.stdout.write(f"RT scheduler stopped after {cycles} cycles ({errors} failed)")
            return
        scheduler = make()
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
