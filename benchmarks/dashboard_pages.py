"""The dashboard's heavy pages at scale (issue 13) and the bulk store of a schedule (issue 15), side by side
with another checkout (the baseline: by default `main` at the merge base, checked out with `git worktree add`).

For each checkout, one subprocess (that checkout's code, its own fresh PostgreSQL database) stores:

- a 310-task layered DAG scheduled by HEFT on 8 processors (one frame),
- a 1000-task layered DAG scheduled for 10 frames (10,000 assignments),
- a 10,000-task layered DAG (one frame),
- two small real DAGs with no schedule: Montage (58 tasks, 114 edges) and the robot STG (90 tasks, 135 edges),
  whose application pages drew an arrow head per edge as a Plotly annotation (1.2-1.6 s of CPU, issue 30),
- 99 copies of the 1000 x 10 schedule (100 in all, 1,000,000 assignment rows), 100 jobs and 100 comparisons
  (JSON columns of realistic size) for the list pages,

then measures through Django's test client (in-process: the server's time for the whole request, every
middleware included, gzip too) the schedule page, the application page and the API's schedule detail at each
size, and the schedules, applications, comparisons and jobs lists with 100 schedules stored: bytes raw and
gzip-compressed (what the browser receives with ``Accept-Encoding: gzip``) and the median server time over
``--repeats`` requests after one warm-up request (one request when the warm-up took more than 5 s), and
the CPU time the server process spent on it (a load-independent figure on a shared machine).
Storing: ``Schedule.store`` of the 1000 x 10 schedule (10,000 assignments), median of ``--repeats`` (each in
a rolled-back transaction).

    python benchmarks/dashboard_pages.py [--base REF | --base-root PATH] [--repeats 3] [--small-only] [--json]

Needs PostgreSQL (``DATABASE_URL``'s server; databases ``<name>_bench_head`` and ``<name>_bench_base`` are
created and dropped). Goals printed next to the figures: the 1000 x 10 schedule page under 500 kB gzipped and
1 s; list pages under 200 ms with 100 schedules; 10,000 assignments stored in under 1 s; the 58- and 90-task
application pages under 0.2 s of server CPU.
"""

from __future__ import annotations

import argparse
import gzip
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from urllib.parse import urlsplit, urlunsplit

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks._bench import drop_database, recreate_database  # noqa: E402

SIZES = [("310", 310, 1), ("1000x10", 1000, 10), ("10000", 10_000, 1)]
#: Small real DAGs (tests/data) whose application pages are measured too: (size label, file).
SMALL_DAGS = [("58 montage", "montage-chameleon-2mass-005d-001.json"), ("90 robot.stg", "robot.stg")]
LIST_COPIES = 99
GOALS = {
    ("schedule page", "1000x10"): (500_000, 1.0),
    ("schedules list", "100 x 1000x10"): (None, 0.2),
    ("applications list", "100 x 1000x10"): (None, 0.2),
    ("comparisons list", "100 x 1000x10"): (None, 0.2),
    ("jobs list", "100 x 1000x10"): (None, 0.2),
    ("store 10,000 assignments", "1000x10"): (None, 1.0),
}
#: Goals on the server's CPU time (load-independent), in seconds.
CPU_GOALS = {("application page", label): 0.2 for label, _ in SMALL_DAGS}


# ---- the worker: runs inside one checkout ---------------------------------------------------------------
def worker(repeats: int, small_only: bool = False) -> dict:
    import django

    os.environ.setdefault("DJANGO_SETTINGS_MODULE", "continuum.settings")
    django.setup()
    from django.core.management import call_command
    from django.db import connection, transaction
    from django.test import Client
    from django.test.utils import setup_test_environment

    from apps.scheduling.models import Assignment, Schedule
    from apps.tenancy.models import Fleet
    from apps.workloads.models import Application
    from continuum.engine.device import algorithms
    from continuum.engine.device.generators import layered_dag, related_platform
    from continuum.engine.formats import load_dag

    setup_test_environment()  # the test client's response.context; ALLOWED_HOSTS gets 'testserver'
    call_command("migrate", verbosity=0)
    from django.contrib.auth import get_user_model

    user = get_user_model().objects.create_user("bench", password="bench-pass-123")
    fleet = Fleet.objects.create(name="bench", slug="bench")
    fleet.members.add(user)
    client = Client()
    client.force_login(user)

    figures: list[dict] = []
    platform = related_platform(8, seed=1)
    stored: dict[str, Schedule] = {}
    engine_schedules = {}
    for label, n, frames in [] if small_only else SIZES:
        dag = layered_dag(n, seed=3, processors=8)
        app = Application(fleet=fleet, source_format="continuum", name=f"layered-{label}")
        app.set_graph(dag)
        app.save()
        params = {"frames": frames} if frames > 1 else {}
        result = algorithms.run("heft", dag, platform, **params)
        engine_schedules[label] = result
        with transaction.atomic():
            stored[label] = Schedule.store(result, application=app, platform=platform)

    def measure(page: str, size: str, url: str) -> None:
        times, raw, packed = [], 0, 0
        start = time.perf_counter()
        client.get(url, HTTP_ACCEPT_ENCODING="gzip")  # warm-up: imports, template loading, database caches
        repeats_here = 1 if time.perf_counter() - start > 5 else repeats
        cpus = []
        for _ in range(repeats_here):
            start, cpu = time.perf_counter(), time.process_time()
            response = client.get(url, HTTP_ACCEPT_ENCODING="gzip")
            times.append(time.perf_counter() - start)
            cpus.append(time.process_time() - cpu)
            assert response.status_code == 200, (url, response.status_code)
            body = b"".join(response.streaming_content) if response.streaming else response.content
            if response.get("Content-Encoding") == "gzip":
                packed, raw = len(body), len(gzip.decompress(body))
            else:
                raw, packed = len(body), len(gzip.compress(body))
                packed = -packed  # not compressed by the server: the size it would have been, marked
        figures.append(
            {
                "page": page,
                "size": size,
                "url": url,
                "raw": raw,
                "gzip": packed,
                "seconds": statistics.median(times),
                "cpu": statistics.median(cpus),
            }
        )

    for label, name in SMALL_DAGS:
        small = Application(fleet=fleet, source_format="continuum", name=name)
        small.set_graph(load_dag((ROOT / "tests" / "data" / name).read_bytes()))
        small.save()
        measure("application page", label, f"/applications/{small.pk}/")
    if small_only:
        return {"figures": figures}

    for label, _, _ in SIZES:
        s = stored[label]
        measure("schedule page", label, f"/schedules/{s.pk}/")
        measure("application page", label, f"/applications/{s.application_id}/")
        measure("API schedule detail", label, f"/api/v1/schedules/{s.pk}/")

    # 100 schedules of the 1000 x 10 size: copies of its rows, made inside the database.
    source = stored["1000x10"]
    columns = [f.column for f in Assignment._meta.concrete_fields if f.column not in ("id", "schedule_id")]
    q = connection.ops.quote_name
    cols = ", ".join(q(c) for c in columns)
    with transaction.atomic(), connection.cursor() as cursor:
        for _ in range(LIST_COPIES):
            copy = Schedule.objects.create(
                fleet=fleet,
                application=source.application,
                platform=source.platform,
                algorithm=source.algorithm,
                params=source.params,
                makespan=source.makespan,
                ranks=source.ranks,
                metrics=source.metrics,
            )
            cursor.execute(
                f"INSERT INTO {q(Assignment._meta.db_table)} ({q('schedule_id')}, {cols}) "
                f"SELECT %s, {cols} FROM {q(Assignment._meta.db_table)} WHERE {q('schedule_id')} = %s",
                [copy.pk, source.pk],
            )
        # A job and a comparison per copy, with JSON columns of a realistic size, for the jobs and comparisons lists.
        from apps.jobs.models import Job
        from apps.scheduling.models import Comparison

        for _ in range(LIST_COPIES + 1):
            Job.objects.create(
                fleet=fleet,
                kind="schedule",
                state="succeeded",
                progress=100,
                arguments={"application": source.application_id, "algorithm": "heft", "platform": source.platform},
                result={"schedule": source.pk, "makespan": source.makespan},
                created_by=user,
            )
            Comparison.objects.create(
                fleet=fleet,
                application=source.application,
                platform=source.platform,
                algorithms=["heft", "xeft"],
                params={"frames": 10},
                result={"results": {"heft": source.metrics}, "ranks": source.ranks, "best": "heft"},
                best="heft",
            )
    with connection.cursor() as cursor:
        cursor.execute("ANALYZE")
    size = f"{LIST_COPIES + 1} x 1000x10"
    measure("schedules list", size, "/schedules/")
    measure("applications list", size, "/applications/")
    measure("comparisons list", size, "/comparisons/")
    measure("jobs list", size, "/jobs/")

    # Storing: the 1000 x 10 schedule again, rolled back each time.
    app = source.application
    times, cpus = [], []
    for _ in range(repeats):
        try:
            with transaction.atomic():
                start, cpu = time.perf_counter(), time.process_time()
                Schedule.store(engine_schedules["1000x10"], application=app, platform=platform)
                times.append(time.perf_counter() - start)
                cpus.append(time.process_time() - cpu)
                raise _Rollback
        except _Rollback:
            pass
    n = len(engine_schedules["1000x10"].assignments)
    figures.append(
        {
            "page": "store 10,000 assignments",
            "size": "1000x10",
            "url": f"{n} rows",
            "raw": 0,
            "gzip": 0,
            "seconds": statistics.median(times),
            "cpu": statistics.median(cpus),
        }
    )
    return {"figures": figures}


class _Rollback(Exception):
    pass


# ---- the orchestrator ----------------------------------------------------------------------------------
def database_url(suffix: str) -> str:
    url = os.environ.get("DATABASE_URL", "postgres://postgres@127.0.0.1:5432/continuum")
    parts = urlsplit(url)
    if not parts.scheme.startswith("postgres"):
        sys.exit("DATABASE_URL must name a PostgreSQL server")
    name = parts.path.lstrip("/") or "continuum"
    return urlunsplit(parts._replace(path=f"/{name}_bench_{suffix}"))


def run_checkout(root: Path, suffix: str, repeats: int, small_only: bool = False) -> dict:
    url = database_url(suffix)
    recreate_database(url)
    env = {**os.environ, "DATABASE_URL": url, "PYTHONPATH": str(root), "DEBUG": "0"}
    env.pop("CELERY_BROKER_URL", None)
    env.pop("CONTINUUM_STATIC_MANIFEST", None)
    print(f"measuring {root} ...", file=sys.stderr, flush=True)
    try:
        out = subprocess.run(
            [sys.executable, str(Path(__file__).resolve()), "--worker", "--repeats", str(repeats)]
            + (["--small-only"] if small_only else []),
            cwd=root,
            env=env,
            capture_output=True,
            text=True,
        )
    finally:
        drop_database(url)
    if out.returncode:
        sys.exit(f"{root}: the worker failed:\n{out.stderr[-4000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def base_checkout(ref: str) -> Path:
    path = Path(tempfile.mkdtemp(prefix="continuum-base-"))
    subprocess.run(
        ["git", "-C", str(ROOT), "worktree", "add", "--detach", str(path), ref], check=True, capture_output=True
    )
    return path


def kb(n: int) -> str:
    if n < 0:
        return f"({-n / 1000:.1f} kB)"  # the server did not compress it: what gzip would make of it
    return f"{n / 1000:.1f} kB" if n else "-"


def report(head: dict, base: dict, base_name: str) -> None:
    rows = {(f["page"], f["size"]): f for f in base["figures"]}
    print(f"dashboard pages: this checkout (head) against {base_name} (base), same machine, one run")
    print("kB = 1000 bytes; gzip = bytes on the wire with Accept-Encoding: gzip (in parentheses: the server sent")
    print("it uncompressed, the figure is what gzip would make of it); s = median server time per request (wall);")
    print("cpu s = the CPU time of the server process for it (the database's own work not included): on a machine")
    print("shared with other jobs, wall time grows with the load and cpu time much less\n")
    header = (
        "page",
        "size",
        "head raw",
        "head gzip",
        "head s",
        "head cpu s",
        "base raw",
        "base gzip",
        "base s",
        "base cpu s",
        "time x",
        "wire x",
        "goal",
    )
    lines = []
    for f in head["figures"]:
        b = rows.get((f["page"], f["size"]))
        goal = GOALS.get((f["page"], f["size"]))
        cpu_goal = CPU_GOALS.get((f["page"], f["size"]))
        goal_text = ""
        if cpu_goal:
            goal_text = f"cpu < {cpu_goal:g} s: " + ("met" if f["cpu"] < cpu_goal else "MISSED")
        if goal:
            size_goal, time_goal = goal
            ok = f["seconds"] < time_goal and (size_goal is None or 0 < f["gzip"] < size_goal)
            goal_text = (
                "< "
                + (f"{size_goal / 1000:.0f} kB, " if size_goal else "")
                + f"{time_goal:g} s: "
                + ("met" if ok else "MISSED")
            )
        wire = lambda x: abs(x["gzip"]) or 1  # noqa: E731
        lines.append(
            (
                f["page"],
                f["size"],
                kb(f["raw"]),
                kb(f["gzip"]),
                f"{f['seconds']:.3f}",
                f"{f['cpu']:.3f}",
                kb(b["raw"]) if b else "?",
                kb(b["gzip"]) if b else "?",
                f"{b['seconds']:.3f}" if b else "?",
                f"{b['cpu']:.3f}" if b else "?",
                f"{b['seconds'] / f['seconds']:.1f}x faster" if b else "?",
                f"{wire(b) / wire(f):.1f}x smaller" if b and f["gzip"] else "",
                goal_text,
            )
        )
    widths = [max(len(h), *(len(r[i]) for r in lines)) for i, h in enumerate(header)]
    print("  ".join(h.ljust(w) for h, w in zip(header, widths, strict=True)))
    for r in lines:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)))


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--base", default="main", help="git ref of the baseline (checked out with git worktree add)")
    p.add_argument("--base-root", type=Path, help="an existing checkout to use as the baseline instead")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--json", action="store_true")
    p.add_argument("--small-only", action="store_true", help="only the small DAGs' application pages (seconds)")
    p.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        sys.path.insert(0, os.getcwd())
        print(json.dumps(worker(args.repeats, args.small_only)))
        return
    base_root = args.base_root
    made = None
    if base_root is None:
        made = base_root = base_checkout(args.base)
    try:
        base = run_checkout(base_root, "base", args.repeats, args.small_only)
        head = run_checkout(ROOT, "head", args.repeats, args.small_only)
    finally:
        if made is not None:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(made)], capture_output=True)
    if args.json:
        print(json.dumps({"head": head, "base": base}))
    else:
        report(head, base, str(args.base_root) if args.base_root else args.base)


if __name__ == "__main__":
    main()
