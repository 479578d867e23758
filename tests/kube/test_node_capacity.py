"""Node sync keeps the declared capacity as the planning input and stores what Kubernetes reports beside it
(issue 12): a kubemark hollow node reports 1 CPU / 3840Mi whatever board the cluster file describes, and a
real node's allocatable may differ from its datasheet too. A node sync found by itself plans with what
Kubernetes reports, until an operator declares its capacity."""

import pytest

from continuum.devcluster import HOLLOW_CAPACITY
from tests.heft4k.fan import run

pytestmark = [pytest.mark.kube, pytest.mark.django_db]

REPORTED_CPU = float(HOLLOW_CAPACITY["cpu"])
REPORTED_MIB = 3840
assert HOLLOW_CAPACITY["memory"] == f"{REPORTED_MIB}Mi"


def test_sync_keeps_the_declared_capacity_and_stores_the_reported_one(api, hollow_cluster):
    from apps.clusters.models import ComputeNode

    cluster = hollow_cluster([{"name": "hollow-a", "cpu": 4, "memory_mib": 8192, "storage_mib": 64000}])
    job = run(api, f"/api/v1/clusters/{cluster.pk}/sync/")
    assert job["state"] == "succeeded", job

    declared = cluster.nodes.get(name="hollow-a")
    assert (declared.cpu, declared.memory_mib, declared.storage_mib) == (4.0, 8192, 64000)  # the board, kept
    assert (declared.reported_cpu, declared.reported_memory_mib) == (REPORTED_CPU, REPORTED_MIB)
    assert declared.capacity_source == "declared" and declared.status == "Ready"
    # The planning input is the declared capacity: what the schedulers and placers see.
    assert cluster.to_engine().nodes["hollow-a"].cpu == 4.0

    # A node Kubernetes has and the file did not declare: planned with what Kubernetes reports.
    found = cluster.nodes.get(name="hollow-b")
    assert found.capacity_source == "reported"
    assert (found.cpu, found.memory_mib) == (found.reported_cpu, found.reported_memory_mib) == (1.0, REPORTED_MIB)
    assert found.arch == "arm64"

    # The API shows both; what Kubernetes reports is not writable.
    shown = api.get(f"/api/v1/nodes/{declared.pk}/").data
    assert (shown["cpu"], shown["reported_cpu"], shown["capacity_source"]) == (4.0, REPORTED_CPU, "declared")
    response = api.patch(f"/api/v1/nodes/{found.pk}/", {"reported_cpu": 64, "cpu": 2}, format="json")
    assert response.status_code == 200, response.data
    # Declaring a capacity makes it the planning input from now on: the next sync keeps it.
    assert (response.data["cpu"], response.data["reported_cpu"], response.data["capacity_source"]) == (
        2.0,
        REPORTED_CPU,
        "declared",
    )
    again = run(api, f"/api/v1/clusters/{cluster.pk}/sync/")
    assert again["state"] == "succeeded", again
    assert again["result"]["created"] == 0
    found.refresh_from_db()
    assert (found.cpu, found.reported_cpu, found.capacity_source) == (2.0, REPORTED_CPU, "declared")
    assert ComputeNode.objects.get(pk=declared.pk).cpu == 4.0
