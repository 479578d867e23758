"""Issue 28: HEFT4K bound pods onto the RT server tainted RealTime=RT:NoSchedule (its pods carry no toleration and
are bound by name, which bypasses Kubernetes' own check). The DAG schedulers now place only on the nodes the one
taint filter admits, as RT-Kube and super-clustering do."""

from __future__ import annotations

import pytest

from tests.api.test_fleet_isolation import FAN_DAG, _job

pytestmark = pytest.mark.django_db


@pytest.mark.parametrize("algorithm", ["heft4k", "heft"])
def test_dag_schedulers_leave_tainted_rt_and_unknown_nodes_alone(api, cluster, algorithm):
    node0 = cluster.nodes.get(name="node0")
    node0.rt, node0.taints = True, [{"key": "RealTime", "value": "RT", "effect": "NoSchedule"}]  # as kube_sync reads it
    node0.save()
    cluster.nodes.filter(name="node3").update(status="Unknown")
    app = api.post("/api/v1/applications/", {"name": "fan", "dag": FAN_DAG}, format="json").data
    job = _job(api, f"/api/v1/applications/{app['id']}/schedule/", {"algorithm": algorithm, "cluster": cluster.pk})
    schedule = api.get(f"/api/v1/schedules/{job['result']['schedule']}/").data
    used = {a["processor"] for a in schedule["assignments"]}
    assert used and used <= {"node1", "node2"}, used
