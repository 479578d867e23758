"""Internal errors reach callers as an error id (the traceback stays in the log); the audit trail."""

import logging
import re

import pytest
from auditlog.models import LogEntry
from django.contrib.contenttypes.models import ContentType

from apps.clusters.models import Cluster
from apps.jobs.models import Job
from apps.jobs.registry import HANDLERS
from apps.jobs.services import start_job
from apps.tenancy.api import FleetViewSet

UUID = re.compile(r"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}")


def crash(*args, **kwargs):
    secret = {"path": "/srv/continuum/secret_settings.py"}
    return secret["missing key"]  # KeyError, as a bug would raise


def test_unexpected_api_error_is_a_500_with_an_error_id_and_the_traceback_only_logged(api, monkeypatch, caplog):
    monkeypatch.setattr(FleetViewSet, "get_queryset", crash)
    with caplog.at_level(logging.ERROR, logger="apps.tenancy.api"):
        response = api.get("/api/v1/fleets/")
    assert response.status_code == 500
    body = response.json()
    assert set(body) == {"detail", "error_id"} and body["detail"] == "internal error"
    assert UUID.fullmatch(body["error_id"])
    text = response.content.decode()
    assert "Traceback" not in text and ".py" not in text and "missing key" not in text
    logged = [r for r in caplog.records if body["error_id"] in r.getMessage()]
    assert logged and logged[0].exc_info and logged[0].exc_info[0] is KeyError


def test_input_errors_stay_400_with_their_message(api):
    response = api.post("/api/v1/applications/", {"name": "x", "dag": {"tasks": "nope"}}, format="json")
    assert response.status_code == 400 and "error_id" not in response.data


def test_crashed_job_exposes_a_reason_and_error_id_but_no_traceback(api, fleet, monkeypatch, caplog):
    monkeypatch.setitem(HANDLERS, "crashes", crash)
    with caplog.at_level(logging.ERROR, logger="apps.jobs.tasks"):
        job = start_job("crashes", fleet, {})
    assert job.state == Job.State.FAILED
    response = api.get(f"/api/v1/jobs/{job.pk}/")
    assert response.status_code == 200
    data = response.json()
    error_id = data["result"]["error_id"]
    assert UUID.fullmatch(error_id)
    assert data["error"] == f"internal error (KeyError); error id {error_id}" and "\n" not in data["error"]
    text = response.content.decode()
    assert "Traceback" not in text and ".py" not in text and "secret" not in text
    logged = [r for r in caplog.records if error_id in r.getMessage()]
    assert logged and logged[0].exc_info[0] is KeyError


def test_job_input_errors_keep_their_message(fleet, monkeypatch):
    from continuum.engine.core.errors import InputError

    def cycle(job, progress):
        raise InputError("cycle: a -> b -> a")

    monkeypatch.setitem(HANDLERS, "cyclic", cycle)
    job = start_job("cyclic", fleet, {})
    assert (job.state, job.error, job.result) == (Job.State.FAILED, "cycle: a -> b -> a", None)


# ---- audit trail --------------------------------------------------------------------------------------------
def entries(model, pk):
    return LogEntry.objects.filter(content_type=ContentType.objects.get_for_model(model), object_pk=str(pk))


def test_api_changes_by_a_token_are_recorded_with_actor_token_and_request_id(api, fleet_token, cluster_doc):
    response = api.post(
        "/api/v1/clusters/import/", {"name": "edge", **cluster_doc}, format="json", HTTP_X_REQUEST_ID="req-42"
    )
    # The id is the server's (issue 25: a caller-chosen id went into the trail); the caller's is kept apart.
    rid = response.headers["X-Request-ID"]
    assert response.status_code == 201 and re.fullmatch(r"[0-9a-f]{32}", rid)
    assert response.headers["X-Client-Request-ID"] == "req-42"
    pk = response.data["id"]
    created = entries(Cluster, pk).get(action=LogEntry.Action.CREATE)
    assert created.actor == fleet_token.user and created.cid == rid
    token = {"token": fleet_token.prefix, "fleet": fleet_token.fleet.slug, "scope": "operator"}
    assert created.additional_data == {"client_request_id": "req-42", **token}
    response = api.patch(f"/api/v1/clusters/{pk}/", {"description": "north site"}, format="json")
    assert response.status_code == 200
    updated = entries(Cluster, pk).get(action=LogEntry.Action.UPDATE)
    assert updated.actor == fleet_token.user and updated.changes_dict["description"] == ["", "north site"]
    assert UUID.fullmatch(updated.cid) or re.fullmatch(r"[0-9a-f]{32}", updated.cid)
    assert api.delete(f"/api/v1/clusters/{pk}/").status_code == 204
    assert entries(Cluster, pk).get(action=LogEntry.Action.DELETE).actor == fleet_token.user


def test_session_changes_name_the_operator_and_secrets_stay_out(client, operator, cluster):
    client.force_login(operator)
    response = client.patch(
        f"/api/v1/clusters/{cluster.pk}/", {"description": "via the browser"}, content_type="application/json"
    )
    assert response.status_code == 200, response.content
    entry = entries(Cluster, cluster.pk).get(action=LogEntry.Action.UPDATE)
    assert entry.actor == operator and entry.additional_data is None
    assert "kubeconfig" not in (entry.changes_dict or {})


def test_reports_are_not_in_the_audit_trail(api, cluster):
    from ..realtime.test_api import report

    body = {"cluster": cluster.pk, "reports": [report()] * 3}
    assert api.post("/api/v1/rt-reports/", body, format="json").status_code == 201  # creates the RT policy
    before = LogEntry.objects.count()
    assert api.post("/api/v1/rt-reports/", body, format="json").status_code == 201
    assert LogEntry.objects.count() == before


@pytest.mark.parametrize("path", ["/admin/auditlog/logentry/"])
def test_audit_trail_is_in_the_admin(admin_client, api, cluster_doc, path):
    api.post("/api/v1/clusters/import/", {"name": "audited", **cluster_doc}, format="json")
    page = admin_client.get(path)
    assert page.status_code == 200 and "audited" in page.content.decode()


def test_changes_a_job_makes_in_a_worker_name_whoever_started_it(api, operator, fleet, cluster):
    from apps.jobs.tasks import run_job
    from apps.scheduling.models import Schedule
    from apps.workloads.models import Application

    dag = {"tasks": [{"id": "a", "cost": {"cpu": 1}}, {"id": "b", "cost": {"cpu": 2}}],
           "edges": [{"src": "a", "dst": "b"}]}  # fmt: skip
    app = api.post("/api/v1/applications/", {"name": "t", "dag": dag}, format="json")
    assert app.status_code == 201, app.data
    # As a worker runs it: outside any request, the job's creator is the actor.
    job = Job.objects.create(
        kind="schedule",
        fleet=fleet,
        created_by=operator,
        arguments={"application": app.data["id"], "algorithm": "heft", "cluster": cluster.pk},
    )
    assert run_job(str(job.pk)) == Job.State.SUCCEEDED, Job.objects.get(pk=job.pk).error
    schedule = Schedule.objects.get(application=Application.objects.get(pk=app.data["id"]))
    entry = entries(Schedule, schedule.pk).get(action=LogEntry.Action.CREATE)
    assert entry.actor == operator and entry.additional_data == {"job": str(job.pk), "kind": "schedule"}


def test_request_ids_are_the_servers_even_when_the_caller_sends_one(api):
    ids = set()
    for given in ("same", "same", "x" * 65, "bad id"):
        response = api.get("/api/v1/clusters/", HTTP_X_REQUEST_ID=given)
        ids.add(response.headers["X-Request-ID"])
        assert response.headers.get("X-Client-Request-ID") == (given if given == "same" else None)
    assert len(ids) == 4 and "same" not in ids


def test_the_trail_records_the_connections_address_not_a_forged_forwarded_for(cluster_doc, fleet_token):
    from rest_framework.test import APIClient

    caller = APIClient(REMOTE_ADDR="192.0.2.7")
    caller.credentials(HTTP_AUTHORIZATION=f"Token {fleet_token.plaintext}")
    body = {"name": "forged", **cluster_doc}
    response = caller.post("/api/v1/clusters/import/", body, format="json", HTTP_X_FORWARDED_FOR="10.9.9.9")
    assert response.status_code == 201
    entry = entries(Cluster, response.data["id"]).get(action=LogEntry.Action.CREATE)
    assert entry.remote_addr == "192.0.2.7"


def test_the_trail_takes_the_address_a_trusted_proxy_appended(settings, cluster_doc, fleet_token):
    from rest_framework.test import APIClient

    settings.CONTINUUM_NUM_PROXIES = 1
    caller = APIClient(REMOTE_ADDR="127.0.0.1")  # the proxy
    caller.credentials(HTTP_AUTHORIZATION=f"Token {fleet_token.plaintext}")
    body = {"name": "proxied", **cluster_doc}
    # The caller wrote the first entry; the proxy appended the address it saw.
    forwarded = "10.9.9.9, 198.51.100.4"
    response = caller.post("/api/v1/clusters/import/", body, format="json", HTTP_X_FORWARDED_FOR=forwarded)
    entry = entries(Cluster, response.data["id"]).get(action=LogEntry.Action.CREATE)
    assert entry.remote_addr == "198.51.100.4"


def test_users_groups_and_permissions_are_in_the_trail(django_user_model):
    from django.contrib.auth.models import Group, Permission

    def changed(model, pk) -> set[str]:
        return {field for e in entries(model, pk) for field in (e.changes_dict or {})}

    user = django_user_model.objects.create_user("newcomer", password="newcomer-pass-123")
    group = Group.objects.create(name="operators")
    permission = Permission.objects.get(codename="change_cluster")
    group.permissions.add(permission)
    user.groups.add(group)
    user.user_permissions.add(permission)
    user.is_superuser = True
    user.set_password("another-pass-456")
    user.save()
    assert entries(django_user_model, user.pk).filter(action=LogEntry.Action.CREATE).exists()
    assert {"groups", "user_permissions", "is_superuser"} <= changed(django_user_model, user.pk)
    assert "password" not in changed(django_user_model, user.pk)  # not even its hash
    assert {"name", "permissions"} <= changed(Group, group.pk)
    made = Permission.objects.create(codename="audit_probe", name="probe", content_type=permission.content_type)
    assert entries(Permission, made.pk).filter(action=LogEntry.Action.CREATE).exists()
