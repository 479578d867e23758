"""Applications: creation, import (continuum JSON, WfFormat), validation, and scheduling jobs."""

import json

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile

from continuum.engine import TaskGraph
from continuum.engine.core.schedule import Schedule as EngineSchedule

pytestmark = pytest.mark.django_db


def upload(api, name, content, **extra):
    return api.post(
        "/api/v1/applications/import/", {"file": SimpleUploadedFile(name, content), **extra}, format="multipart"
    )


def run_schedule(api, app_id, **body):
    response = api.post(f"/api/v1/applications/{app_id}/schedule/", body, format="json")
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded", job
    return api.get(job["result_url"]).data


def test_topcuoglu_on_its_platform_gives_makespan_80(api, load_json):
    app = api.post("/api/v1/applications/", {"name": "t", "dag": load_json("topcuoglu.dag.json")}, format="json")
    assert app.status_code == 201, app.data
    assert app.data["task_count"] == 10 and app.data["edge_count"] == 15
    schedule = run_schedule(api, app.data["id"], algorithm="heft", platform=load_json("topcuoglu.platform.json"))
    assert schedule["format"] == "continuum.schedule/v1"
    assert schedule["makespan"] == 80
    assert len(schedule["assignments"]) == 10
    assert round(schedule["ranks"]["0"], 3) == 108


def test_montage_imports_and_schedules_validly_on_a_4_node_cluster(api, cluster, data_dir):
    content = (data_dir / "montage-chameleon-2mass-005d-001.json").read_bytes()
    response = upload(api, "montage.json", content)
    assert response.status_code == 201, response.data
    assert response.data["source_format"] == "wfformat" and response.data["task_count"] == 58
    schedule = run_schedule(api, response.data["id"], algorithm="heft", cluster=cluster.pk)
    engine = EngineSchedule.from_dict(schedule)
    dag = TaskGraph.from_dict(api.get(f"/api/v1/applications/{response.data['id']}/").data["dag"])
    assert engine.violations(dag, cluster.to_platform()) == []
    assert {a.processor for a in engine.assignments} <= {f"node{i}" for i in range(4)}
    # Four nodes must beat running everything on one: the serial sum of runtimes.
    assert engine.makespan < sum(t.cost["cpu"] for t in dag.tasks.values())


@pytest.mark.parametrize(
    ("dag", "needle"),
    [
        (
            {
                "tasks": [{"id": "a", "cost": {"cpu": 1}}, {"id": "b", "cost": {"cpu": 1}}],
                "edges": [{"src": "a", "dst": "b"}, {"src": "b", "dst": "a"}],
            },
            "cycle",
        ),
        ({"tasks": [{"id": "a", "cost": {"cpu": 1}}], "edges": [{"src": "a", "dst": "ghost"}]}, "ghost"),
        ({"tasks": [{"id": "a", "cost": {"cpu": 1}}, {"id": "a", "cost": {"cpu": 2}}], "edges": []}, "duplicate"),
        ({"tasks": [{"id": "a", "cost": {"cpu": -3}}], "edges": []}, "'a'"),
        ({"tasks": [], "edges": []}, "tasks"),
    ],
)
def test_bad_dag_is_rejected_with_its_culprit_and_not_stored(api, dag, needle):
    from apps.workloads.models import Application

    response = api.post("/api/v1/applications/", {"name": "bad", "dag": dag}, format="json")
    assert response.status_code == 400
    assert needle in str(response.data["dag"])
    assert Application.objects.count() == 0


def test_malformed_upload_names_the_line(api):
    response = upload(api, "broken.json", b'{"tasks": [\n  {"id": "a",, }\n]}')
    assert response.status_code == 400
    assert "line 2" in str(response.data["file"])


def test_task_no_processor_can_run_fails_the_job_naming_it(api, cluster):
    dag = {"tasks": [{"id": "gpu-only", "cost": {"gpu": 3}}], "edges": []}
    app = api.post("/api/v1/applications/", {"name": "g", "dag": dag}, format="json").data
    response = api.post(f"/api/v1/applications/{app['id']}/schedule/", {"cluster": cluster.pk}, format="json")
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "failed" and "'gpu-only' cannot run" in job["error"]


def test_schedule_request_needs_exactly_one_target(api, cluster, load_json):
    app = api.post("/api/v1/applications/", {"name": "t", "dag": load_json("topcuoglu.dag.json")}, format="json").data
    url = f"/api/v1/applications/{app['id']}/schedule/"
    assert api.post(url, {}, format="json").status_code == 400
    both = {"cluster": cluster.pk, "platform": load_json("topcuoglu.platform.json")}
    assert api.post(url, both, format="json").status_code == 400
    bad = api.post(url, {"algorithm": "nope", "cluster": cluster.pk}, format="json")
    assert bad.status_code == 400 and "algorithm" in bad.data
    bad_platform = api.post(url, {"platform": {"processors": []}}, format="json")
    assert bad_platform.status_code == 400 and "platform" in bad_platform.data


def test_other_fleet_cannot_schedule_on_my_cluster(api, other_api, cluster, load_json):
    app = other_api.post(
        "/api/v1/applications/", {"name": "t", "dag": load_json("topcuoglu.dag.json")}, format="json"
    ).data
    response = other_api.post(f"/api/v1/applications/{app['id']}/schedule/", {"cluster": cluster.pk}, format="json")
    assert response.status_code == 400 and "cluster" in response.data


def test_job_records_progress_and_timings(api, load_json):
    app = api.post("/api/v1/applications/", {"name": "t", "dag": load_json("topcuoglu.dag.json")}, format="json").data
    response = api.post(
        f"/api/v1/applications/{app['id']}/schedule/", {"platform": load_json("topcuoglu.platform.json")}, format="json"
    )
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["progress"] == 100 and job["attempts"] == 1
    assert job["started"] and job["finished"] and job["duration"] >= 0
    assert json.loads(json.dumps(job["arguments"]))["application"] == app["id"]
