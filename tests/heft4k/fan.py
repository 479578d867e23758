"""A fan-out/fan-in DAG that HEFT4K spreads over the conftest's 4-node edge cluster (4 CPUs each).

On that cluster the plan puts the source, the (critical) sink and 8 workers on node0 and 4 workers on each
of node1-node3: losing node1, node2 or node3 costs about 18-19% of the total rank (partial remap at the
default 20% threshold), losing node0 loses the critical sink (total remap).
"""

WORKERS = 20
FAN_DAG = {
    "format": "continuum.dag/v1",
    "name": "Fan 20",
    "tasks": [
        {"id": "src", "cost": {"cpu": 2}},
        *({"id": f"w{i:02d}", "cost": {"cpu": 10 + i % 3}} for i in range(WORKERS)),
        {"id": "sink", "cost": {"cpu": 3}, "critical": True},
    ],
    "edges": [
        *({"src": "src", "dst": f"w{i:02d}", "data": 0.5} for i in range(WORKERS)),
        *({"src": f"w{i:02d}", "dst": "sink", "data": 0.5} for i in range(WORKERS)),
    ],
}


def run(api, url: str, body: dict | None = None) -> dict:
    """POST an action that starts a job and return the job (jobs run in-process: no broker in tests)."""
    response = api.post(url, body or {}, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] in ("succeeded", "failed"), job
    return job


def heft4k_schedule(api, cluster, dag: dict | None = None, **params):
    """Create the application and a HEFT4K schedule of it on ``cluster`` through the API; the Schedule row."""
    from apps.scheduling.models import Schedule

    dag = dag or FAN_DAG
    response = api.post("/api/v1/applications/", {"name": dag["name"], "dag": dag}, format="json")
    assert response.status_code == 201, response.data
    body = {"algorithm": "heft4k", "cluster": cluster.pk, "params": params}
    job = run(api, f"/api/v1/applications/{response.data['id']}/schedule/", body)
    assert job["state"] == "succeeded", job
    return Schedule.objects.get(pk=job["result"]["schedule"])


def nodes_of(schedule) -> dict[str, str]:
    return dict(schedule.assignments.values_list("task", "processor"))
