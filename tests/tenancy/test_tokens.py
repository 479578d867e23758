"""Fleet tokens: hashed at rest, shown once, scoped (robot / operator), optionally expiring."""

import hashlib
from datetime import timedelta

import pytest
from django.core.management import call_command
from django.db import connection
from django.db.migrations.executor import MigrationExecutor
from django.utils import timezone
from rest_framework.test import APIClient

from apps.tenancy.models import FleetToken

from ..realtime.test_api import report


def client_for(key: str) -> APIClient:
    client = APIClient()
    client.credentials(HTTP_AUTHORIZATION=f"Token {key}")
    return client


@pytest.fixture
def robot_token(fleet, django_user_model):
    robot = django_user_model.objects.create_user("sensor-robot")
    return FleetToken.objects.create_token(fleet=fleet, user=robot, scope=FleetToken.Scope.ROBOT)


# ---- hashing ------------------------------------------------------------------------------------------------
def test_key_is_stored_only_as_its_hash_and_given_once(fleet, django_user_model):
    user = django_user_model.objects.create_user("r1")
    token, key = FleetToken.objects.create_token(fleet=fleet, user=user)
    assert len(key) >= 40 and token.prefix == key[:8]
    stored = FleetToken.objects.get(pk=token.pk)
    assert stored.plaintext is None and stored.key_hash == hashlib.sha256(key.encode()).hexdigest()
    with connection.cursor() as cursor:
        cursor.execute("SELECT * FROM tenancy_fleettoken WHERE id = %s", [token.pk])
        row = cursor.fetchone()
    assert not any(isinstance(value, str) and key in value for value in row)
    # Keys differ token to token, and the scope of a token created without one is "operator".
    other, other_key = FleetToken.objects.create_token(fleet=fleet, user=user)
    assert other_key != key and other.key_hash != token.key_hash and token.scope == "operator"


def test_authentication_by_key_and_unknown_or_altered_keys_are_refused(fleet_token, fleet):
    key = fleet_token.plaintext
    response = client_for(key).get("/api/v1/fleets/")
    assert response.status_code == 200 and [f["slug"] for f in response.data["results"]] == [fleet.slug]
    for bad in (key[:-1] + ("A" if key[-1] != "A" else "B"), key[:8], fleet_token.key_hash, "x" * 40):
        response = client_for(bad).get("/api/v1/fleets/")
        assert response.status_code == 401 and response.data["detail"] == "invalid token"


def test_expired_token_answers_401_token_expired(fleet, django_user_model):
    user = django_user_model.objects.create_user("r2")
    token, key = FleetToken.objects.create_token(fleet=fleet, user=user, expires=timezone.now() + timedelta(hours=1))
    assert client_for(key).get("/api/v1/clusters/").status_code == 200
    FleetToken.objects.filter(pk=token.pk).update(expires=timezone.now() - timedelta(seconds=1))
    response = client_for(key).get("/api/v1/clusters/")
    assert response.status_code == 401 and response.data["detail"] == "token expired"


def test_last_use_is_recorded_at_most_once_a_minute(fleet_token):
    client = client_for(fleet_token.plaintext)
    assert client.get("/api/v1/clusters/").status_code == 200
    first = FleetToken.objects.get(pk=fleet_token.pk).last_used
    assert first is not None
    assert client.get("/api/v1/clusters/").status_code == 200
    assert FleetToken.objects.get(pk=fleet_token.pk).last_used == first
    FleetToken.objects.filter(pk=fleet_token.pk).update(last_used=first - timedelta(minutes=2))
    assert client.get("/api/v1/clusters/").status_code == 200
    assert FleetToken.objects.get(pk=fleet_token.pk).last_used > first - timedelta(minutes=2)


# ---- scopes -------------------------------------------------------------------------------------------------
def test_robot_token_reads_and_reports_but_cannot_change_the_fleet(robot_token, cluster, cluster_doc):
    from apps.realtime.models import MonitoringReport

    robot = client_for(robot_token[1])
    response = robot.post("/api/v1/clusters/import/", {"name": "edge2", **cluster_doc}, format="json")
    assert response.status_code == 403 and "robot" in response.data["detail"]
    assert robot.patch(f"/api/v1/clusters/{cluster.pk}/", {"name": "x"}, format="json").status_code == 403
    assert robot.delete(f"/api/v1/clusters/{cluster.pk}/").status_code == 403
    assert robot.post("/api/v1/assertions/", {"name": "a", "text": "G(x > 0)"}, format="json").status_code == 403
    cluster.refresh_from_db()
    assert cluster.name == "edge"
    # Reads: everything of its fleet.
    for path in ("clusters", "nodes", "applications", "jobs", "rt-reports", "rt-monitorings", "monitors"):
        assert robot.get(f"/api/v1/{path}/").status_code == 200, path
    assert robot.get(f"/api/v1/clusters/{cluster.pk}/").data["name"] == "edge"
    # Writes where robots write: missed-deadline reports and verification events.
    response = robot.post("/api/v1/rt-reports/", {"cluster": cluster.pk, "reports": [report()]}, format="json")
    assert response.status_code == 201, response.data
    assert MonitoringReport.objects.filter(cluster=cluster).count() == 1
    response = robot.post("/api/v1/events/", {"cluster": cluster.pk, "events": [["speed", 1, 0]]}, format="json")
    assert response.status_code in (200, 202), response.data


def test_operator_tokens_and_sessions_change_the_fleet(api, cluster, cluster_doc, client, operator):
    response = api.post("/api/v1/clusters/import/", {"name": "edge2", **cluster_doc}, format="json")
    assert response.status_code == 201, response.data
    client.force_login(operator)
    response = client.patch(f"/api/v1/clusters/{cluster.pk}/", {"name": "renamed"}, content_type="application/json")
    assert response.status_code == 200, response.content


def test_changing_a_token_scope_takes_effect_on_the_next_request(fleet_token, cluster_doc):
    FleetToken.objects.filter(pk=fleet_token.pk).update(scope=FleetToken.Scope.ROBOT)
    client = client_for(fleet_token.plaintext)
    assert client.post("/api/v1/clusters/import/", {"name": "e", **cluster_doc}, format="json").status_code == 403
    # Saved (the admin, the API): the processes that kept the robot token drop it (see test_token_cache.py).
    token = FleetToken.objects.get(pk=fleet_token.pk)
    token.scope = FleetToken.Scope.OPERATOR
    token.save()
    assert client.post("/api/v1/clusters/import/", {"name": "e", **cluster_doc}, format="json").status_code == 201


# ---- admin and the demo -------------------------------------------------------------------------------------
def test_admin_shows_a_new_key_once_and_never_again(admin_client, fleet, django_user_model):
    robot = django_user_model.objects.create_user("admin-made-robot")
    response = admin_client.post(
        "/admin/tenancy/fleettoken/add/",
        {
            "fleet": fleet.pk,
            "user": robot.pk,
            "scope": "robot",
            "description": "lidar",
            "expires_0": "",
            "expires_1": "",
        },
        follow=True,
    )
    assert response.status_code == 200
    token = FleetToken.objects.get(description="lidar")
    shown = [str(m) for m in response.context["messages"]]
    key = next(m.split("<code>")[1].split("</code>")[0] for m in shown if "<code>" in m)
    assert token.prefix == key[:8] and token.matches(key) and token.scope == "robot"
    assert client_for(key).get("/api/v1/clusters/").status_code == 200
    page = admin_client.get(f"/admin/tenancy/fleettoken/{token.pk}/change/").content.decode()
    assert token.prefix in page and key not in page and token.key_hash not in page
    for path in ("/admin/tenancy/fleettoken/", f"/admin/tenancy/fleet/{fleet.pk}/change/"):
        page = admin_client.get(path).content.decode()
        assert token.prefix in page and key not in page and token.key_hash not in page


def test_load_demo_prints_a_working_token_and_keeps_it(db, tmp_path, settings, capsys):
    settings.VAR_DIR = tmp_path
    call_command("load_demo")
    first = capsys.readouterr().out
    key = first.split("fleet token for the API: ")[1].split(")")[0]
    assert client_for(key).get("/api/v1/clusters/").data["count"] == 1
    call_command("load_demo")
    again = capsys.readouterr().out
    assert f"fleet token for the API: {key})" in again and FleetToken.objects.count() == 1
    assert key in (tmp_path / "demo-credentials.txt").read_text()


# ---- migration ----------------------------------------------------------------------------------------------
@pytest.mark.django_db(transaction=True)
def test_migration_hashes_existing_keys_and_they_keep_working(django_user_model):
    executor = MigrationExecutor(connection)
    executor.migrate([("tenancy", "0001_initial")])
    old = executor.loader.project_state([("tenancy", "0001_initial")]).apps
    fleet = old.get_model("tenancy", "Fleet").objects.create(name="Legacy", slug="legacy")
    user = old.get_model("auth", "User").objects.create(username="legacy-robot")
    key = "0123456789abcdef0123456789abcdef01234567"
    old.get_model("tenancy", "FleetToken").objects.create(key=key, fleet=fleet, user=user)
    executor = MigrationExecutor(connection)
    executor.migrate(executor.loader.graph.leaf_nodes())
    token = FleetToken.objects.get(fleet__slug="legacy")
    assert token.prefix == "01234567" and token.matches(key) and token.scope == "operator"
    with connection.cursor() as cursor:
        columns = [c.name for c in connection.introspection.get_table_description(cursor, "tenancy_fleettoken")]
    assert "key" not in columns
    assert client_for(key).get("/api/v1/fleets/").data["results"][0]["slug"] == "legacy"


def test_token_added_in_the_fleet_page_is_shown_once(admin_client, fleet, django_user_model):
    robot = django_user_model.objects.create_user("inline-robot")
    form = {
        "name": fleet.name, "slug": fleet.slug, "description": "",
        "tokens-TOTAL_FORMS": "1", "tokens-INITIAL_FORMS": "0", "tokens-MIN_NUM_FORMS": "0",
        "tokens-MAX_NUM_FORMS": "1000", "tokens-0-user": robot.pk, "tokens-0-scope": "robot",
        "tokens-0-description": "arm", "tokens-0-expires_0": "", "tokens-0-expires_1": "", "tokens-0-fleet": fleet.pk,
    }  # fmt: skip
    response = admin_client.post(f"/admin/tenancy/fleet/{fleet.pk}/change/", form, follow=True)
    assert response.status_code == 200
    token = FleetToken.objects.get(description="arm")
    shown = " ".join(str(m) for m in response.context["messages"])
    key = shown.split("<code>")[1].split("</code>")[0]
    assert token.matches(key) and token.fleet == fleet and token.scope == "robot"
