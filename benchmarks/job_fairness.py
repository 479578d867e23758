"""Fleets take turns for the job workers (issue 25): one fleet's backlog must not delay another fleet's job by
more than one job's run time.

Real parts: PostgreSQL (a throw-away database, ``BENCH_DB``), Redis (``--broker``; a private queue), a Celery
worker process (``--concurrency`` slots; 1: the strictest case). Fleet A queues ``--backlog`` scheduling jobs
(HEFT on a ``--tasks``-task layered DAG, 16 processors); once its first job runs, fleet B queues one short job
(``--short-tasks``). Printed: one A job's run time (median), B's wait (queued -> started) and the ratio, how many
A jobs started before B's, the CPU seconds of the worker (with its pool) and of this driver, the load average.
A's backlog is then cancelled, so the run ends soon.

    python benchmarks/job_fairness.py [--backlog 120 --tasks 1000 --short-tasks 20 --concurrency 1]
        [--broker redis://127.0.0.1:6379/0] [--before REV]

``--before REV`` runs the same measurement first at git revision REV (a temporary worktree; this script is copied
into it), then here: before/after from one run each.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import random
import resource
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
import uuid
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks._bench import loadavg, recreate_database  # noqa: E402

PLATFORM = {"processors": [{"id": f"p{i}", "class": "cpu", "speed": 1 + i % 3} for i in range(16)],
            "bandwidth": 2.0, "latency": 0.1}  # fmt: skip


def layered_dag(n: int, seed: int = 7) -> dict:
    rng = random.Random(seed)
    tasks = [{"id": f"t{i}", "cost": {"cpu": rng.uniform(1, 50)}} for i in range(n)]
    edges = {(f"t{rng.randrange(max(0, j - 50), j)}", f"t{j}") for j in range(1, n) for _ in range(2)}
    return {"name": f"layered-{n}", "tasks": tasks,
            "edges": [{"src": s, "dst": d, "data": rng.uniform(0, 5)} for s, d in sorted(edges)]}  # fmt: skip


def cpu_of(usage) -> float:
    return usage.ru_utime + usage.ru_stime


def measure(args) -> None:
    base = os.environ.get("DATABASE_URL", "postgres://postgres@127.0.0.1:5432/continuum")
    url = recreate_database(base.rsplit("/", 1)[0] + "/" + os.environ.get("BENCH_DB", "continuum_bench_fairness"))
    queue = f"bench-fairness-{uuid.uuid4().hex[:8]}"
    env = {"DATABASE_URL": url, "CELERY_BROKER_URL": args.broker, "CELERY_QUEUE": queue, "CONTINUUM_JOBS_EAGER": "0",
           "DJANGO_SETTINGS_MODULE": "continuum.settings", "LOG_LEVEL": "WARNING"}  # fmt: skip
    os.environ.update(env)
    import django

    django.setup()
    from django.core.management import call_command

    call_command("migrate", verbosity=0)
    from apps.jobs.models import Job
    from apps.jobs.services import cancel_job, start_job
    from apps.scheduling.kinds import SchedulingJob
    from apps.tenancy.models import Fleet
    from apps.workloads.models import Application
    from continuum.engine import TaskGraph

    def application(fleet, n):
        app = Application(fleet=fleet, name=f"dag-{n}")
        app.set_graph(TaskGraph.from_dict(layered_dag(n)))
        app.save()
        return app

    def schedule(fleet, app):
        return start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft",
                                                         "platform": PLATFORM})  # fmt: skip

    def wait(job_id, until, timeout=3600.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            job = Job.objects.get(pk=job_id)
            if until(job):
                return job
            time.sleep(0.02)
        raise SystemExit(f"job {job_id} still {job.state} after {timeout:g} s")

    alpha, beta = Fleet.objects.create(name="Fleet A"), Fleet.objects.create(name="Fleet B")
    big, small = application(alpha, args.tasks), application(beta, args.short_tasks)
    log = Path(tempfile.gettempdir()) / f"{queue}.log"
    load_before = loadavg()
    worker = subprocess.Popen(
        [sys.executable, "-m", "celery", "-A", "continuum", "worker", "-Q", queue, "--without-gossip",
         "--without-mingle", "--loglevel=WARNING",
         *(["-P", "solo"] if args.concurrency == 1 else ["-P", "prefork", "-c", str(args.concurrency)])],
        cwd=ROOT, env={**os.environ, **env}, stdout=log.open("w"), stderr=subprocess.STDOUT,
    )  # fmt: skip
    try:
        backlog = [schedule(alpha, big) for _ in range(args.backlog)]
        wait(backlog[0].pk, lambda j: j.state != Job.State.PENDING)
        late = schedule(beta, small)
        late = wait(late.pk, lambda j: j.done)
        ahead = Job.objects.filter(fleet=alpha, started__lt=late.started).count()
        for job in Job.objects.filter(fleet=alpha, state=Job.State.PENDING):
            with contextlib.suppress(ValueError):  # taken by the worker meanwhile: it runs to its end
                cancel_job(job)
        for job in backlog:
            wait(job.pk, lambda j: j.done)
    finally:
        worker.send_signal(signal.SIGTERM)
        _, _, usage = os.wait4(worker.pid, 0)
    runs = [j.duration for j in Job.objects.filter(fleet=alpha, state=Job.State.SUCCEEDED) if j.duration]
    run = statistics.median(runs)
    waited = (late.started - late.created).total_seconds()
    driver = cpu_of(resource.getrusage(resource.RUSAGE_SELF))
    print(f"revision {args.label}: backlog {args.backlog} jobs of fleet A ({args.tasks} tasks), "
          f"{args.concurrency} worker slot(s)")  # fmt: skip
    print(f"  one A job runs {run:.3f} s (median of {len(runs)}); fleet B's job ({args.short_tasks} tasks) "
          f"waited {waited:.3f} s = {waited / run:.2f} A jobs; {ahead} A job(s) started before it")  # fmt: skip
    print(f"  CPU s: worker {cpu_of(usage):.1f}, driver {driver:.1f}; load average {load_before} -> {loadavg()}")
    print(f"  B's job: {late.state}, {late.duration:.3f} s run")
    log.unlink(missing_ok=True)


def at_revision(rev: str, argv: list[str]) -> None:
    """This measurement at git revision ``rev``, in a temporary worktree (this script copied into it)."""
    tree = Path(tempfile.mkdtemp(prefix="job-fairness-"))
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "-q", "--detach", str(tree), rev], check=True)
    try:
        for name in ("job_fairness.py", "_bench.py"):
            shutil.copy(ROOT / "benchmarks" / name, tree / "benchmarks" / name)
        env = {**os.environ, "PYTHONPATH": str(tree)}
        subprocess.run([sys.executable, str(tree / "benchmarks" / "job_fairness.py"), *argv, "--label", rev],
                       cwd=tree, env=env, check=True)  # fmt: skip
    finally:
        subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)], check=False)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--backlog", type=int, default=120)
    parser.add_argument("--tasks", type=int, default=1000)
    parser.add_argument("--short-tasks", type=int, default=20)
    parser.add_argument("--concurrency", type=int, default=1)
    parser.add_argument("--broker", default=os.environ.get("BENCH_BROKER", "redis://127.0.0.1:6379/0"))
    parser.add_argument("--before", help="a git revision to measure first, for before/after")
    parser.add_argument("--label", default="this checkout", help=argparse.SUPPRESS)
    args = parser.parse_known_args()[0]
    if args.before:
        argv = [a for a in sys.argv[1:] if not a.startswith("--before") and a != args.before]
        at_revision(args.before, argv)
    measure(args)


if __name__ == "__main__":
    main()
