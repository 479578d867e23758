"""Table 4.34 measured: the real reconcile (``apps.realtime.monitoring.ingest``) on PostgreSQL, swept over the
container count on the violating node, the RT share and the three victim policies (used by
``benchmarks/thesis.py``; ``python benchmarks/thesis_reconcile.py`` prints the table alone).

Each cell: a throw-away database (``DATABASE_URL``'s server, database ``<name>_t434``), one cluster with one RT
node holding ``n`` pods (``n_rt`` RealTime ones of class A, the others best-effort; all stateless, so each is a
candidate victim), one class-B violator, and a missed-deadline report over the threshold ingested through the
same function the REST endpoint calls; the time is the ingest's wall time (store, lock, ledger read, the engine's
victim selection under the policy, the event, taint and eviction records). No Kubernetes API is configured, so
the eviction is recorded but not sent: the thesis' figure includes the API round trip, ours does not (``how =
real processes``, inputs untuned). Median of ``repeats`` reconciles per cell, each on fresh pods.
"""

from __future__ import annotations

import os
import statistics
import sys
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

#: spec 03 section 12.5: (n, non-RT, RT) -> ms for linear, linearithmic, quadratic.
THESIS_4_34 = {
    (1, 1, 0): (41.07, 40.81, 40.83),
    (1, 0, 1): (41.75, 41.49, 41.51),
    (8, 8, 0): (40.26, 39.27, 57.27),
    (8, 4, 4): (42.98, 41.99, 59.99),
    (8, 0, 8): (45.70, 44.71, 62.71),
    (16, 16, 0): (51.32, 51.62, 157.94),
    (16, 8, 8): (56.76, 57.06, 163.38),
    (16, 0, 16): (62.20, 62.50, 168.82),
    (32, 32, 0): (65.43, 106.07, 173.57),
    (32, 16, 16): (70.87, 111.51, 179.01),
    (32, 0, 32): (76.31, 116.95, 184.45),
    (64, 64, 0): (115.23, 152.39, 687.02),
    (64, 32, 32): (126.11, 163.27, 697.90),
    (64, 0, 64): (136.99, 174.15, 708.08),
}
POLICIES = ("linear", "linearithmic", "quadratic")


def _setup() -> str:
    from _bench import recreate_database

    base = os.environ.get("DATABASE_URL", "postgres://postgres@127.0.0.1:5432/continuum")
    if not base.startswith("postgres"):
        raise SystemExit("Table 4.34 needs PostgreSQL: set DATABASE_URL=postgres://...")
    url = base.rsplit("/", 1)[0] + "/" + base.rsplit("/", 1)[1].split("?")[0] + "_t434"
    recreate_database(url)
    os.environ["DATABASE_URL"] = url
    os.environ.setdefault("DJANGO_SETTINGS_MODULE", "continuum.settings")
    import django

    django.setup()
    from django.core.management import call_command

    call_command("migrate", verbosity=0)
    return url


def _cell(cluster: Any, node: Any, n: int, n_rt: int, policy: str, run: int) -> float:
    from apps.realtime import monitoring
    from apps.realtime.models import RealTime, RealTimeWcet, RTPod, RTPolicy

    RTPolicy.objects.filter(cluster=cluster).update(eviction_policy=policy)
    RTPod.objects.filter(cluster=cluster).delete()
    prefix = f"r{run}"
    violator = RealTime.objects.create(
        cluster=cluster, namespace=cluster.namespace, name=f"{prefix}-ctl", criticality="B", period=100, deadline=100
    )
    RealTimeWcet.objects.create(realtime=violator, node=node, wcet=10)
    pods = [
        RTPod(
            cluster=cluster,
            namespace=cluster.namespace,
            name=f"{prefix}-ctl",
            uid=f"uid-{prefix}-ctl",
            node=node.name,
            container_name=f"{prefix}-ctl",
            criticality="B",
            stateless=False,
            cpu=0.5,
            realtime=violator,
            utilization=0.1,
            scheduler_name="RT-scheduler",
        )
    ]
    for k in range(n):
        rt = k < n_rt
        pods.append(
            RTPod(
                cluster=cluster,
                namespace=cluster.namespace,
                name=f"{prefix}-c{k}",
                uid=f"uid-{prefix}-c{k}",
                node=node.name,
                container_name=f"{prefix}-c{k}",
                criticality="A" if rt else "NONE",
                stateless=True,
                cpu=0.05,
                memory_mib=64,
                utilization=0.01 + 0.001 * k if rt else None,
                scheduler_name="RT-scheduler",
            )
        )
    RTPod.objects.bulk_create(pods)
    [report] = monitoring.parse_batch(
        [
            {
                "node": node.name,
                "containerName": f"{prefix}-ctl",
                "missedDeadlinesPeriod": 50,
                "missedDeadlinesTotal": 50,
                "report_id": f"{prefix}-{policy}-{n}-{n_rt}",
            }
        ]
    )
    started = time.perf_counter()
    result = monitoring.ingest(cluster, [report], policy=RTPolicy.for_cluster(cluster))
    elapsed = (time.perf_counter() - started) * 1000
    if not result["events"]:
        raise RuntimeError(f"no reconcile event for n={n} rt={n_rt} {policy}: {result}")
    return elapsed


def sweep(repeats: int = 5) -> dict[str, Any]:
    """Median reconcile time (ms) per Table 4.34 cell and policy, with the thesis' values beside."""
    url = _setup()
    from apps.clusters.models import Cluster, ComputeNode
    from apps.realtime.models import NodeTaint, RTEvent, RTPolicy
    from apps.tenancy.models import Fleet

    fleet = Fleet.objects.create(name="t434")
    cluster = Cluster.objects.create(fleet=fleet, name="t434", namespace="t434")
    node = ComputeNode.objects.create(cluster=cluster, name="rt0", cpu=8, memory_mib=16384, rt=True, criticality="A")
    RTPolicy.objects.create(cluster=cluster, threshold_period=10, taint_duration_s=0)
    cells: dict[str, Any] = {}
    run = 0
    try:
        for (n, non_rt, n_rt), thesis in THESIS_4_34.items():
            ours = []
            for policy in POLICIES:
                times = []
                for _ in range(repeats):
                    run += 1
                    NodeTaint.objects.all().delete()
                    RTEvent.objects.all().delete()
                    times.append(_cell(cluster, node, n, n_rt, policy, run))
                ours.append(round(statistics.median(times), 2))
            cells[f"{n} ({non_rt}-{n_rt})"] = {"thesis_ms": list(thesis), "ours_ms": ours}
    finally:
        from django.db import connections

        connections.close_all()
        from _bench import drop_database

        drop_database(url)
    return {"policies": list(POLICIES), "cells": cells, "repeats": repeats}


if __name__ == "__main__":
    out = sweep()
    print(f"{'n (nonRT-RT)':<14}" + "".join(f"{p:>28}" for p in POLICIES))
    for key, cell in out["cells"].items():
        print(
            f"{key:<14}"
            + "".join(
                f"{t:>12.2f} thesis {o:>7.2f} ours" for t, o in zip(cell["thesis_ms"], cell["ours_ms"], strict=True)
            )
        )
