"""Job kinds are a typed registry: each app declares its kinds (a JobKind StrEnum) and registers a handler per
kind; start_job refuses anything unregistered, and Job.kind keeps the plain strings."""

import pytest

from apps.clusters.kinds import ClusterJob
from apps.containers.kinds import ContainersJob
from apps.heft4k.kinds import Heft4kJob
from apps.jobs.models import Job
from apps.jobs.registry import HANDLERS, KINDS, JobKind, UnknownJobKind, job_kind, resolve
from apps.jobs.services import start_job
from apps.realtime.kinds import RealtimeJob
from apps.scheduling.kinds import SchedulingJob
from apps.verification.kinds import VerificationJob
from apps.workloads.models import Application
from continuum.engine.core.dag import TaskGraph

pytestmark = pytest.mark.django_db

DECLARED = [*SchedulingJob, *ClusterJob, *ContainersJob, *Heft4kJob, *RealtimeJob, *VerificationJob]

#: The strings stored in Job.kind (database rows, API output, the fleet client): they never change.
STORED = {
    "schedule", "compare", "push_schedule", "sync_cluster", "cluster_ros", "place", "push_placement", "remap",
    "remap_apply", "heft4k_simulate", "rt_whatif", "rt_sync", "rt_push", "rt_delete", "rt_reports", "allocate_monitors",
    "verification_simulation", "build_images",
}  # fmt: skip


def test_every_declared_kind_has_a_handler_and_keeps_its_stored_string():
    assert {kind.value for kind in DECLARED} == STORED
    assert set(HANDLERS) == set(KINDS) == STORED
    for kind in DECLARED:
        assert isinstance(kind, JobKind) and KINDS[kind.value] is kind
        assert HANDLERS[kind] is HANDLERS[kind.value]  # a member finds its handler like its string does


def test_start_job_refuses_an_unregistered_kind_and_records_nothing(fleet):
    with pytest.raises(UnknownJobKind, match=r"unknown job kind 'shedule'.*registered: .*schedule"):
        start_job("shedule", fleet, {})
    with pytest.raises(ValueError, match="unknown job kind"):  # UnknownJobKind is a ValueError
        resolve(42)
    assert not Job.objects.exists()


def test_job_kind_takes_only_declared_kinds():
    with pytest.raises(TypeError, match="JobKind members"):
        job_kind("schedule")


def test_a_kind_has_one_handler():
    def other(job, progress):
        return {}, ""

    with pytest.raises(ValueError, match="already has a handler"):
        job_kind(SchedulingJob.SCHEDULE)(other)
    assert HANDLERS["schedule"] is not other


def test_the_stored_kind_is_the_plain_string(fleet):
    app = Application(fleet=fleet, name="one")
    dag = {"format": "continuum.dag/v1", "name": "one", "tasks": [{"id": "a", "cost": {"cpu": 1}}], "edges": []}
    app.set_graph(TaskGraph.from_dict(dag))
    app.save()
    platform = {"format": "continuum.platform/v1", "processors": [{"id": "cpu0", "class": "cpu"}]}
    job = start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft", "platform": platform})
    row = Job.objects.get(pk=job.pk)
    assert type(row.kind) is str and row.kind == "schedule" and row.state == "succeeded", row.error
    assert Job.objects.filter(kind=SchedulingJob.SCHEDULE).count() == 1
