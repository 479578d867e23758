"""Responses are gzip-compressed when the client accepts it (issue 13), by Django's GZipMiddleware."""

import gzip
import json

import pytest

from apps.workloads.models import Application
from continuum.engine.formats import load_dag
from tests.conftest import DATA

pytestmark = pytest.mark.django_db

URL = "/api/v1/applications/"


@pytest.fixture
def many_applications(fleet):
    graph = load_dag((DATA / "topcuoglu.dag.json").read_bytes())
    for i in range(30):
        app = Application(fleet=fleet, source_format="continuum", name=f"app-{i}")
        app.set_graph(graph)
        app.save()


def test_a_large_api_list_is_gzipped_when_accepted(api, many_applications):
    plain = api.get(URL)
    assert plain.status_code == 200
    assert "Content-Encoding" not in plain
    doc = json.loads(plain.content)
    assert doc["count"] == 30

    packed = api.get(URL, HTTP_ACCEPT_ENCODING="gzip, deflate")
    assert packed.status_code == 200
    assert packed["Content-Encoding"] == "gzip"
    assert "Accept-Encoding" in packed["Vary"]
    assert json.loads(gzip.decompress(packed.content)) == doc
    assert len(packed.content) < len(plain.content) / 3, (len(packed.content), len(plain.content))
    print(f"{URL}: {len(plain.content)} bytes plain, {len(packed.content)} gzipped")


def test_a_dashboard_page_is_gzipped_and_still_carries_a_masked_csrf_token(client, operator, many_applications):
    client.force_login(operator)
    pages = [client.get("/applications/", HTTP_ACCEPT_ENCODING="gzip") for _ in range(2)]
    tokens = []
    for page in pages:
        assert page.status_code == 200 and page["Content-Encoding"] == "gzip"
        html = gzip.decompress(page.content).decode()
        tokens.append(html.split('name="csrfmiddlewaretoken" value="', 1)[1].split('"', 1)[0])
    assert len(tokens[0]) == 64 and tokens[0] != tokens[1]  # masked afresh on every response (the BREACH mitigation)
