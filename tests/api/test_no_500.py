"""The causes of 500 found in issue 25, each a 400 (or 413) naming the problem now: a form's ``constants=null``,
a lone surrogate echoed in an error message, costs that overflowed to inf/NaN inside the heft4k and xeft jobs
(and the heft4k command). Django's body bounds inside DRF: tests/api/test_body_limits.py."""

from __future__ import annotations

import json

import pytest

from apps.heft4k.management.commands.heft4k import Command as Heft4kCommand
from apps.jobs.models import Job
from apps.verification.models import Assertion
from apps.workloads.models import Application

pytestmark = pytest.mark.django_db

FORM = "application/x-www-form-urlencoded"


def dag(cost: float = 3.0, data: float = 1.0) -> dict:
    return {
        "format": "continuum.dag/v1",
        "name": "big",
        "tasks": [{"id": f"t{i}", "cost": {"cpu": cost, "gpu": cost}} for i in range(3)],
        "edges": [{"src": "t0", "dst": "t1", "data": data}, {"src": "t1", "dst": "t2", "data": data}],
    }


@pytest.mark.parametrize("body", ["name=a&text=G(x>0)&constants=null", "name=a&text=G(x>0)&constants=NaN"])
def test_a_form_json_field_that_is_null_or_nan_is_a_400(api, body):
    response = api.generic("POST", "/api/v1/assertions/", body, content_type=FORM)
    assert response.status_code == 400, response.content
    assert "constants" in response.json()
    assert not Assertion.objects.exists()


def test_a_form_json_field_with_numbers_still_works(api):
    body = 'name=a&text=G(x>0)&constants={"timeout": 5}'
    response = api.generic("POST", "/api/v1/assertions/", body, content_type=FORM)
    assert response.status_code == 201, response.content
    assert Assertion.objects.get().constants == {"timeout": 5}


@pytest.mark.parametrize(
    ("path", "body", "field"),
    [
        ("/api/v1/placements/run/", b'{"policy": "\\ud800"}', "policy"),
        ("/api/v1/applications/generate/", b'{"generator": "\\udfff"}', "generator"),
    ],
)
def test_a_lone_surrogate_is_refused_without_a_500(api, path, body, field):
    response = api.generic("POST", path, body, content_type="application/json")
    assert response.status_code == 400, response.content
    assert field in response.json()
    assert "\\ud" in response.content.decode().lower() or "surrogate" in response.content.decode()


def test_a_lone_surrogate_in_a_json_document_is_refused_naming_its_path(api):
    body = json.dumps({"name": "s", "dag": {**dag(), "meta": {"note": "\ud800"}}}).encode()
    response = api.generic("POST", "/api/v1/applications/", body, content_type="application/json")
    assert response.status_code == 400 and "surrogate" in response.content.decode(), response.content
    assert not Application.objects.exists()


@pytest.mark.parametrize(("cost", "data"), [(1e308, 1.0), (1.0, 1e308), (1e13, 1.0)])
def test_costs_that_would_overflow_a_schedule_are_refused_on_import(api, cost, data):
    response = api.post("/api/v1/applications/", {"name": "big", "dag": dag(cost, data)}, format="json")
    assert response.status_code == 400, response.data
    assert "at most" in json.dumps(response.data) or "0 to 1e+12" in json.dumps(response.data)
    assert not Application.objects.exists()


@pytest.mark.parametrize("algorithm", ["heft4k", "xeft"])
def test_the_largest_costs_and_slowest_platform_allowed_give_a_finite_schedule(api, algorithm):
    app = api.post("/api/v1/applications/", {"name": "big", "dag": dag(1e12, 1e12)}, format="json")
    assert app.status_code == 201, app.data
    platform = {
        "format": "continuum.platform/v1",
        "processors": [{"id": "c0", "class": "cpu", "speed": 1e-6}, {"id": "g0", "class": "gpu", "speed": 1e-6}],
        "bandwidth": 1e-6,
        "latency": 1e12,
    }
    body = {"algorithm": algorithm, "platform": platform}
    response = api.post(f"/api/v1/applications/{app.data['id']}/schedule/", body, format="json")
    assert response.status_code == 202, response.data
    job = Job.objects.get(pk=response.data["id"])
    assert job.state == Job.State.SUCCEEDED, job.error
    too_slow = {**platform, "processors": [{"id": "c0", "class": "cpu", "speed": 1e-308}]}
    path = f"/api/v1/applications/{app.data['id']}/schedule/"
    response = api.post(path, {**body, "platform": too_slow}, format="json")
    assert response.status_code == 400 and "speed must be from 1e-06" in json.dumps(response.data), response.data


@pytest.mark.parametrize(("cost", "speed"), [(1e308, 1.0), (1.0, 1e-308)])
def test_the_heft4k_command_exits_2_on_costs_that_would_overflow(tmp_path, capsys, cost, speed):
    (tmp_path / "dag.json").write_text(json.dumps(dag(cost)))
    cluster = {"format": "continuum.cluster/v1", "nodes": [{"name": "n1", "cpu": 2, "speed": speed}], "links": []}
    (tmp_path / "cluster.json").write_text(json.dumps(cluster))
    files = [str(tmp_path / "dag.json"), "--cluster", str(tmp_path / "cluster.json")]
    argv = ["manage.py", "heft4k", "--skip-checks", *files]
    with pytest.raises(SystemExit) as exit_:
        Heft4kCommand().run_from_argv(argv)
    assert exit_.value.code == 2
    err = capsys.readouterr().err.strip()
    assert ("1e+12" in err or "1e-06" in err) and "\n" not in err and "Traceback" not in err
