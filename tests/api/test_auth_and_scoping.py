"""Every endpoint needs authentication; a fleet's token sees and changes only its own fleet."""

import pytest
from rest_framework.test import APIClient

pytestmark = pytest.mark.django_db

ENDPOINTS = [
    "/api/v1/fleets/",
    "/api/v1/clusters/",
    "/api/v1/nodes/",
    "/api/v1/links/",
    "/api/v1/applications/",
    "/api/v1/schedules/",
    "/api/v1/jobs/",
    "/api/v1/comparisons/",
    "/api/v1/devices/",
    "/api/schema/",
]


@pytest.mark.parametrize("url", ENDPOINTS)
def test_unauthenticated_calls_are_refused(url):
    response = APIClient().get(url)
    assert response.status_code in (401, 403)


def test_bad_token_is_refused(db):
    client = APIClient()
    client.credentials(HTTP_AUTHORIZATION="Token not-a-real-token")
    assert client.get("/api/v1/clusters/").status_code == 401


def test_fleet_token_cannot_see_other_fleets_cluster(cluster, api, other_api):
    assert api.get(f"/api/v1/clusters/{cluster.pk}/").status_code == 200
    assert other_api.get(f"/api/v1/clusters/{cluster.pk}/").status_code == 404
    assert other_api.get("/api/v1/clusters/").data["count"] == 0
    assert other_api.get("/api/v1/nodes/").data["count"] == 0
    node = cluster.nodes.first()
    assert other_api.get(f"/api/v1/nodes/{node.pk}/").status_code == 404
    assert other_api.delete(f"/api/v1/clusters/{cluster.pk}/").status_code == 404
    assert other_api.patch(f"/api/v1/nodes/{node.pk}/", {"cpu": 1}, format="json").status_code == 404


def test_fleet_token_cannot_create_in_other_fleet(api, fleets):
    response = api.post("/api/v1/clusters/", {"name": "x", "fleet": fleets[1].slug}, format="json")
    assert response.status_code == 400 and "fleet" in response.data


def test_fleet_token_cannot_attach_node_to_other_fleets_cluster(cluster, other_api):
    response = other_api.post("/api/v1/nodes/", {"cluster": cluster.pk, "name": "intruder"}, format="json")
    assert response.status_code == 400 and "cluster" in response.data


def test_operator_session_sees_own_fleets(client, operator, cluster):
    client.force_login(operator)
    data = client.get("/api/v1/clusters/").json()
    assert [c["name"] for c in data["results"]] == ["edge"]


def test_schema_and_docs_for_authenticated_users(api):
    response = api.get("/api/schema/")
    assert response.status_code == 200
    assert b"/api/v1/applications/{id}/schedule/" in response.content
