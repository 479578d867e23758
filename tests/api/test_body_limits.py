"""Request bodies are bounded per endpoint before anything parses them, and every input check is linear in
its size (issue 25: a 919 KiB placement request held a web thread for a minute; Django's own body bounds
raised inside DRF and answered 500)."""

from __future__ import annotations

import json

import pytest
from rest_framework import serializers

from apps.clusters.serializers import ClusterImportSerializer
from apps.jobs.models import Job
from apps.tenancy.bounds import UPLOAD_FRAMING_BYTES
from continuum.engine.core import limits

from ..engine.core.test_linear_checks import Counted


def post_raw(api, path: str, body: bytes, content_type: str = "application/json"):
    return api.generic("POST", path, body, content_type=content_type)


@pytest.mark.django_db
def test_a_body_over_the_endpoints_limit_is_413_naming_the_limit_before_it_is_parsed(api, cluster):
    maximum = limits.get().body_bytes
    body = b'{"name": "' + b"x" * maximum + b'"}'  # a well-formed JSON document one byte too many
    response = post_raw(api, "/api/v1/assertions/", body)
    assert response.status_code == 413
    assert response.json()["limit_bytes"] == maximum and f"at most {maximum:,} bytes" in response.json()["detail"]
    # Not parsed: an unparsable body of the same size gets the same answer, not a parse error.
    assert post_raw(api, "/api/v1/assertions/", b"[" * (maximum + 1)).status_code == 413


@pytest.mark.django_db
def test_a_document_endpoint_takes_bodies_up_to_the_upload_limit(api, cluster):
    # A placement document above body_bytes (padded with whitespace) reaches the serializer: 400 about its
    # content, not 413; above upload_bytes it is refused unread.
    with limits.override(body_bytes=1000, upload_bytes=100_000):
        doc = json.dumps({"cluster": cluster.pk, "containers": {"containers": []}}).encode()
        response = post_raw(api, "/api/v1/placements/run/", doc + b" " * 5000)
        assert response.status_code == 400 and "containers" in response.json()
        response = post_raw(api, "/api/v1/placements/run/", doc + b" " * (100_000 + UPLOAD_FRAMING_BYTES))
        assert response.status_code == 413 and response.json()["limit_bytes"] == 100_000 + UPLOAD_FRAMING_BYTES
        # Any other action of the same viewset keeps the small limit.
        assert post_raw(api, "/api/v1/clusters/", b" " * 1001).status_code == 413
    assert not Job.objects.exists()


@pytest.mark.django_db
def test_a_malformed_content_length_is_400(api):
    response = api.generic("POST", "/api/v1/assertions/", b"{}", content_type="application/json",
                           CONTENT_LENGTH="12abc")  # fmt: skip
    assert response.status_code == 400 and "Content-Length" in response.json()["detail"]


@pytest.mark.django_db
def test_too_many_form_fields_is_400_not_500(api, settings):
    body = "&".join(f"f{i}=1" for i in range(settings.DATA_UPLOAD_MAX_NUMBER_FIELDS + 1)).encode()
    response = post_raw(api, "/api/v1/assertions/", body, "application/x-www-form-urlencoded")
    assert response.status_code == 400
    assert f"at most {settings.DATA_UPLOAD_MAX_NUMBER_FIELDS:,} form fields" in response.json()["detail"]


@pytest.mark.django_db
def test_form_fields_over_djangos_memory_bound_are_413_not_500(api, settings):
    settings.DATA_UPLOAD_MAX_MEMORY_SIZE = 2000  # below the endpoint's limit: Django's bound is met first
    body = b'--B\r\nContent-Disposition: form-data; name="name"\r\n\r\n' + b"x" * 3000 + b"\r\n--B--\r\n"
    response = post_raw(api, "/api/v1/assertions/", body, "multipart/form-data; boundary=B")
    assert response.status_code == 413 and response.json()["limit_bytes"] == 2000


@pytest.mark.django_db
def test_placement_documents_are_bounded_in_containers_and_bandwidth(api, cluster):
    with limits.override(nodes=10, links=10):
        many = {"containers": [{"name": f"c{i}", "cpu": 0.1} for i in range(11)]}
        response = api.post("/api/v1/placements/run/", {"cluster": cluster.pk, "containers": many}, format="json")
        assert response.status_code == 400 and "containers: at most 10 (got 11)" in json.dumps(response.json())
        pairs = [{"a": "c0", "b": "c1", "bytes_per_s": 1}] * 11
        doc = {"containers": [{"name": "c0"}, {"name": "c1"}], "bandwidth": pairs}
        response = api.post("/api/v1/placements/run/", {"cluster": cluster.pk, "containers": doc}, format="json")
        assert response.status_code == 400 and "bandwidth: at most 10 (got 11)" in json.dumps(response.json())
    assert not Job.objects.exists()


def test_a_cluster_documents_links_are_checked_against_its_nodes_in_linear_comparisons():
    n = 3000
    nodes = [{"name": Counted(f"n{i}")} for i in range(n)]
    links = [{"src": Counted(f"n{i}"), "dst": Counted(f"n{i + 1}")} for i in range(n - 1)]
    links.append({"src": "n0", "dst": "nowhere"})  # stops validation before the database is asked
    Counted.calls = 0
    with pytest.raises(serializers.ValidationError, match="refers to unknown node 'nowhere'"):
        ClusterImportSerializer().validate({"fleet": object(), "nodes": nodes, "links": links})
    assert Counted.calls <= 10 * n  # a list lookup per link end: n^2 = 9,000,000
