"""The web app's /metrics: only with CONTINUUM_METRICS_TOKEN set, only to its bearer; parsed by prometheus_client."""

from __future__ import annotations

import pytest

from apps.clusters.models import ComputeNode
from tests.scrape import parse, total

TOKEN = "scrape-" + "x" * 32


@pytest.fixture
def configured(settings):
    settings.CONTINUUM_METRICS_TOKEN = TOKEN
    return TOKEN


def test_not_configured_is_not_found(client, settings):
    settings.CONTINUUM_METRICS_TOKEN = ""
    assert client.get("/metrics").status_code == 404
    assert client.get("/metrics", HTTP_AUTHORIZATION=f"Bearer {TOKEN}").status_code == 404


@pytest.mark.parametrize(
    "header",
    [None, "Bearer wrong-token-of-the-same-kind", f"Token {TOKEN}", f"Basic {TOKEN}", "Bearer", f"Bearer {TOKEN}x"],
)
def test_anyone_without_the_token_is_refused(client, configured, header):
    extra = {"HTTP_AUTHORIZATION": header} if header is not None else {}
    response = client.get("/metrics", **extra)
    assert response.status_code == 401
    assert b"continuum_" not in response.content


def test_a_fleet_token_or_a_session_is_not_a_scraper(client, api, member, configured):
    assert api.get("/metrics").status_code == 401  # the fleet's API token (Authorization: Token ...)
    assert member.get("/metrics").status_code == 401  # a dashboard session of a fleet's operator


def test_the_scraper_reads_requests_jobs_and_the_not_ready_alarm(client, api, cluster, configured):
    assert api.get("/api/v1/clusters/").status_code == 200
    ComputeNode.objects.filter(cluster=cluster).update(status=ComputeNode.Status.UNKNOWN)
    response = client.get("/metrics", HTTP_AUTHORIZATION=f"Bearer {TOKEN}")
    assert response.status_code == 200 and response["Content-Type"].startswith("text/plain")
    families = parse(response.content.decode())
    assert total(families, "continuum_http_requests_total", route="api/v1/clusters/", code="200") >= 1
    nodes = ComputeNode.objects.filter(cluster=cluster).count()
    assert nodes > 0
    assert total(families, "continuum_nodes", status="Unknown") == nodes
    assert total(families, "continuum_nodes_not_ready") == nodes
    assert "continuum_jobs" in families
