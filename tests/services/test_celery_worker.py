"""Scheduling jobs end to end through a real worker process and real Redis."""

import random
import time

import pytest

from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.models import Schedule
from apps.workloads.models import Application
from continuum.engine import TaskGraph

pytestmark = [pytest.mark.services, pytest.mark.django_db(transaction=True)]


def big_dag(n: int, seed: int = 7) -> TaskGraph:
    rng = random.Random(seed)
    tasks = [{"id": f"t{i}", "cost": {"cpu": rng.uniform(1, 50)}} for i in range(n)]
    edges = [
        {"src": f"t{rng.randrange(max(0, j - 50), j)}", "dst": f"t{j}", "data": rng.uniform(0, 5)}
        for j in range(1, n)
        for _ in range(2)
    ]
    unique = {(e["src"], e["dst"]): e for e in edges}
    return TaskGraph.from_dict({"name": f"layered-{n}", "tasks": tasks, "edges": list(unique.values())})


def make_app(fleet, n: int) -> Application:
    app = Application(fleet=fleet, name=f"dag-{n}")
    app.set_graph(big_dag(n))
    app.save()
    return app


def wait_for(job_id, until, timeout: float = 180.0, seen: list | None = None) -> Job:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        job = Job.objects.get(pk=job_id)
        if seen is not None:
            seen.append((job.state, job.progress))
        if until(job):
            return job
        time.sleep(0.01)
    raise AssertionError(f"job {job_id} still {job.state} ({job.progress}%) after {timeout}s")


PLATFORM = {
    "processors": [{"id": f"p{i}", "class": "cpu", "speed": 1 + i % 3} for i in range(16)],
    "bandwidth": 2.0,
    "latency": 0.1,
}


def test_worker_runs_a_scheduling_job_with_progress(fleet, start_worker):
    start_worker()
    app = make_app(fleet, 6000)
    job = start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft", "platform": PLATFORM})
    assert job.state == Job.State.PENDING  # queued, not run in this process
    seen: list = []
    job = wait_for(job.pk, lambda j: j.done, seen=seen)
    assert job.state == Job.State.SUCCEEDED, job.error
    assert any(state == "running" and 0 < progress < 100 for state, progress in seen), seen[:20]
    schedule = Schedule.objects.get(job=job)
    assert schedule.assignments.count() == 6000
    assert job.result == {"schedule": schedule.pk, "makespan": schedule.makespan}
    engine = schedule.to_engine()
    assert engine.violations(app.graph, schedule.engine_platform()) == []


def test_bad_job_fails_cleanly_and_the_worker_carries_on(fleet, start_worker):
    worker = start_worker()
    app = make_app(fleet, 10)
    bad = start_job(
        SchedulingJob.SCHEDULE,
        fleet,
        {"application": app.pk, "algorithm": "heft", "platform": {"processors": [{"id": "g", "class": "gpu"}]}},
    )
    bad = wait_for(bad.pk, lambda j: j.done)
    assert bad.state == Job.State.FAILED and "cannot run on any processor" in bad.error
    good = start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft", "platform": PLATFORM})
    assert wait_for(good.pk, lambda j: j.done).state == Job.State.SUCCEEDED
    assert worker.proc.poll() is None


def test_worker_killed_mid_job_leaves_the_job_retried_not_lost(fleet, start_worker):
    first = start_worker(visibility_timeout=3)
    app = make_app(fleet, 20000)
    job = start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft", "platform": PLATFORM})
    wait_for(job.pk, lambda j: j.state == Job.State.RUNNING and j.progress > 0)
    first.kill()
    assert Job.objects.get(pk=job.pk).state == Job.State.RUNNING  # interrupted, not finished
    start_worker(visibility_timeout=3)
    job = wait_for(job.pk, lambda j: j.done, timeout=300)
    assert job.state == Job.State.SUCCEEDED, job.error
    assert job.attempts == 2
    assert Schedule.objects.filter(job=job).count() == 1
    assert Schedule.objects.get(job=job).assignments.count() == 20000
