"""Fixtures for the dashboard tests: a logged-in operator, an application and a schedule in each fleet."""

import json

import pytest

from apps.scheduling.kinds import SchedulingJob
from tests.conftest import DATA


@pytest.fixture
def member(client, operator):
    """The test client logged in as a member of the first fleet only."""
    client.force_login(operator)
    return client


def make_application(fleet, name="topcuoglu.dag.json"):
    from apps.workloads.models import Application
    from continuum.engine.formats import load_dag

    app = Application(fleet=fleet, source_format="continuum")
    app.set_graph(load_dag((DATA / name).read_bytes()))
    app.name = app.dag["name"]
    app.save()
    return app


def schedule_on_platform(app, platform_doc, user=None):
    """Run a HEFT scheduling job (in-process: no broker in the tests) and return the stored schedule."""
    from apps.jobs.services import start_job
    from apps.scheduling.models import Schedule

    job = start_job(
        SchedulingJob.SCHEDULE,
        app.fleet,
        {"application": app.pk, "algorithm": "heft", "params": {}, "platform": platform_doc},
        user,
    )
    assert job.state == "succeeded", job.error
    return Schedule.objects.get(job=job)


@pytest.fixture
def topcuoglu_platform():
    return json.loads((DATA / "topcuoglu.platform.json").read_text())


@pytest.fixture
def application(fleet):
    return make_application(fleet)


@pytest.fixture
def schedule(application, topcuoglu_platform, operator):
    return schedule_on_platform(application, topcuoglu_platform, operator)


@pytest.fixture
def foreign(fleets, topcuoglu_platform):
    """A cluster, an application, a schedule and a job of the second fleet (which the operator is not in)."""
    from apps.clusters.models import Cluster, ComputeNode

    other = fleets[1]
    cluster = Cluster.objects.create(fleet=other, name="beta-secret-cluster")
    ComputeNode.objects.create(cluster=cluster, name="beta-node")
    app = make_application(other)
    app.name = "beta-secret-app"
    app.save()
    schedule = schedule_on_platform(app, topcuoglu_platform)
    return {"cluster": cluster, "application": app, "schedule": schedule, "job": schedule.job}
