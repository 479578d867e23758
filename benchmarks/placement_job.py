"""The placement job a user starts against the engine under it, in the same run (issue 29).

A random workload and cluster (``tests/engine/containers/superclustering_reference.random_instance``: mixed
archs, taints, affinities, ~4 bandwidth neighbours per container), imported through the API into a throw-away
PostgreSQL database (``<DATABASE_URL's name>_placement_bench``, dropped at the end), then timed side by side:

* **engine**: ``place("superclustering")`` and the default-Kubernetes baseline the job also runs;
* **job**: the ``place`` job's handler (read the inputs, both placements, the bounded explanations, store);
* **shown**: the placement's page, ``GET /api/v1/placements/{id}/``, and one container's ``why`` table,
  stored (bounded) and ``full=1`` (every node's verdict recomputed from the stored inputs);

with CPU time, wall time, the stored plan's size, the process's peak memory (max RSS), whether the stored
placements are the engine's, and the load average. ``--reference N`` also times, at N containers, what the job
stored before: every node's verdict for every container (``plan.to_dict()`` of the full plan).

    python benchmarks/placement_job.py [--containers 5000] [--nodes 500] [--seed 5000] [--reference 1000]
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import pstats
import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from benchmarks._bench import loadavg, table, throwaway_database

GOAL_S, GOAL_MIB = 5.0, 1024.0


def clock(fn):
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def show_profile(prof: cProfile.Profile, what: str) -> None:
    buf = io.StringIO()
    pstats.Stats(prof, stream=buf).sort_stats("tottime").print_stats(10)
    print(f"cProfile of {what} (own time):")
    print("\n".join(line for line in buf.getvalue().splitlines() if line.strip())[-1800:])


def peak_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--containers", type=int, default=5000)
    p.add_argument("--nodes", type=int, default=500)
    p.add_argument("--seed", type=int, default=5000)
    p.add_argument("--profile", action="store_true", help="cProfile the job and the page")
    p.add_argument("--reference", type=int, default=1000, help="containers for the old full-verdict store (0: skip)")
    args = p.parse_args()
    with throwaway_database("_placement_bench"):
        run(args)


def run(args: argparse.Namespace) -> None:
    import django

    django.setup()
    from django.contrib.auth import get_user_model
    from django.core.management import call_command
    from django.test import Client
    from django.test.utils import setup_test_environment

    from apps.containers.models import Placement
    from apps.jobs.models import Job
    from apps.jobs.registry import HANDLERS
    from apps.tenancy.models import Fleet
    from continuum.engine.containers.superclustering import place
    from tests.engine.containers import superclustering_reference as ref

    setup_test_environment()
    call_command("migrate", verbosity=0)
    user = get_user_model().objects.create_user("bench", password="bench-pass-123")
    fleet = Fleet.objects.create(name="bench", slug="bench")
    fleet.members.add(user)
    client = Client()
    client.force_login(user)

    n, m = args.containers, args.nodes
    workload, cluster = ref.random_instance(n, m, seed=args.seed)
    response = client.post(
        "/api/v1/clusters/import/", {"name": "bench", **cluster.to_dict()}, content_type="application/json"
    )
    assert response.status_code == 201, response.content[:500]
    cluster_id = response.json()["id"]
    doc = workload.to_dict()
    print(f"{n} containers x {m} nodes; load average {loadavg()}; peak RSS before {peak_mib():.0f} MiB", flush=True)

    from apps.clusters.models import Cluster
    from apps.containers import services

    engine_cluster = Cluster.objects.get(pk=cluster_id).to_engine()
    workload, _ = services.resolve_workload(doc)  # what the job places: the document as the API read it
    plan, e_wall, e_cpu = clock(lambda: place("superclustering", workload, engine_cluster))
    _, b_wall, b_cpu = clock(lambda: place("default-kubernetes", workload, engine_cluster))

    job = Job.objects.create(kind="place", fleet=fleet, arguments={"cluster": cluster_id, "containers": doc})
    rss_before = peak_mib()
    prof = cProfile.Profile() if args.profile else None
    if prof:
        prof.enable()
    (summary, _), j_wall, j_cpu = clock(lambda: HANDLERS["place"](job, lambda percent, message: None))
    if prof:
        prof.disable()
        show_profile(prof, "the job")
    rss_job = peak_mib()
    row = Placement.objects.get(pk=summary["placement"])
    stored_mib = len(json.dumps(row.plan)) / 2**20
    same = row.placed() == plan.placed()

    def get(url: str):
        response = client.get(url)
        assert response.status_code == 200, (url, response.status_code)
        return response

    container = plan.decisions[len(plan.decisions) // 2].item
    shown, bodies = [], []
    for label, url in (
        ("page /ros/placements/{id}/", f"/ros/placements/{row.pk}/"),
        ("GET /api/v1/placements/{id}/", f"/api/v1/placements/{row.pk}/"),
        ("why?container=X (stored, bounded)", f"/api/v1/placements/{row.pk}/why/?container={container}"),
        ("why?container=X&full=1 (recomputed)", f"/api/v1/placements/{row.pk}/why/?container={container}&full=1"),
    ):
        prof = cProfile.Profile() if args.profile and "page" in label else None
        if prof:
            prof.enable()
        response, wall, cpu = clock(lambda url=url: get(url))
        if prof:
            prof.disable()
            show_profile(prof, label)
        shown.append([label, wall, cpu, f"{len(response.content) / 2**20:.2f}"])
        bodies.append(response.content)
    full_rows = len(json.loads(bodies[3])["rows"])

    rows = [
        ["engine: superclustering", e_wall, e_cpu, "-"],
        ["engine: + default-kubernetes baseline", e_wall + b_wall, e_cpu + b_cpu, "-"],
        ["job: place (both, bounded, stored)", j_wall, j_cpu, f"{stored_mib:.2f}"],
        *shown,
    ]
    print(table(["path", "wall s", "CPU s", "MiB"], rows))
    end_to_end_wall = j_wall + shown[0][1] + shown[1][1]
    end_to_end_cpu = j_cpu + shown[0][2] + shown[1][2]
    print(f"stored placements == engine's: {'yes' if same else 'NO'}; full why: {full_rows} node verdicts")
    print(f"goal: stored and shown < {GOAL_S:.0f} s -> job + page + API detail {end_to_end_wall:.2f} s wall "
          f"({end_to_end_cpu:.2f} s CPU); < {GOAL_MIB:.0f} MiB -> process peak RSS {rss_job:.0f} MiB "
          f"(before the job {rss_before:.0f} MiB)")  # fmt: skip

    if args.reference:
        wl, cl = ref.random_instance(args.reference, m, seed=args.seed)
        full_plan = place("superclustering", wl, cl)
        text, r_wall, r_cpu = clock(lambda: json.dumps(full_plan.to_dict()))
        print(f"before (every node's verdict stored) at {args.reference} x {m}: building the document alone "
              f"{r_wall:.2f} s wall, {r_cpu:.2f} s CPU, {len(text) / 2**20:.1f} MiB")  # fmt: skip
    print(f"load average after: {loadavg()}")


if __name__ == "__main__":
    main()
