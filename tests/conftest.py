"""Fixtures shared by the test suite: fleets, users, tokens and API clients."""

import json
import os
from pathlib import Path

import pytest
from django.conf import settings
from rest_framework.test import APIClient

from apps.scheduling.kinds import SchedulingJob

DATA = Path(__file__).resolve().parent / "data"

# The suite asks for in-process jobs (CONTINUUM_JOBS_EAGER, never the default): a test's request or command
# runs its job before it returns. Commands the tests run as subprocesses inherit it; tests that need a real
# worker (tests/services/conftest.py: celery_broker, start_worker) turn it off for themselves.
os.environ["CONTINUUM_JOBS_EAGER"] = "1"
settings.CELERY_TASK_ALWAYS_EAGER = True


@pytest.fixture
def data_dir() -> Path:
    return DATA


@pytest.fixture
def load_json():
    return lambda name: json.loads((DATA / name).read_text())


@pytest.fixture
def fleets(db):
    from apps.tenancy.models import Fleet

    return Fleet.objects.create(name="Alpha robots"), Fleet.objects.create(name="Beta robots")


@pytest.fixture
def fleet(fleets):
    return fleets[0]


@pytest.fixture
def operator(db, fleet, django_user_model):
    user = django_user_model.objects.create_user("operator", password="operator-pass-123")
    fleet.members.add(user)
    return user


@pytest.fixture
def fleet_token(fleet, django_user_model):
    from apps.tenancy.models import FleetToken

    robot = django_user_model.objects.create_user(f"{fleet.slug}-robot")
    return FleetToken.objects.create(fleet=fleet, user=robot, description="test robot")


@pytest.fixture
def api(fleet_token) -> APIClient:
    """An API client authenticated with the first fleet's token."""
    client = APIClient()
    client.credentials(HTTP_AUTHORIZATION=f"Token {fleet_token.plaintext}")
    return client


@pytest.fixture
def other_api(fleets, django_user_model) -> APIClient:
    """An API client authenticated with the second fleet's token."""
    from apps.tenancy.models import FleetToken

    robot = django_user_model.objects.create_user("beta-robot")
    token = FleetToken.objects.create(fleet=fleets[1], user=robot)
    client = APIClient()
    client.credentials(HTTP_AUTHORIZATION=f"Token {token.plaintext}")
    return client


CLUSTER_DOC = {
    "format": "continuum.cluster/v1",
    "nodes": [
        {"name": f"node{i}", "arch": "amd64", "cpu": 4, "memory_mib": 8192, "labels": {"zone": "edge"}}
        for i in range(4)
    ],
    "links": [{"src": f"node{i}", "dst": f"node{i + 1}", "bandwidth_mbps": 1000, "latency_ms": 0.5} for i in range(3)],
}


@pytest.fixture
def cluster_doc():
    return json.loads(json.dumps(CLUSTER_DOC))


@pytest.fixture
def cluster(api, cluster_doc):
    from apps.clusters.models import Cluster

    response = api.post("/api/v1/clusters/import/", {"name": "edge", **cluster_doc}, format="json")
    assert response.status_code == 201, response.data
    return Cluster.objects.get(pk=response.data["id"])


# ---- dashboard pages (every domain's page tests) ----
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
