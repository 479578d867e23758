"""The interactive API docs load only from our own static files."""

import re

import pytest

pytestmark = pytest.mark.django_db


@pytest.mark.parametrize("url", ["/api/docs/", "/api/redoc/"])
def test_docs_pages_use_no_cdn(api, url):
    response = api.get(url)
    assert response.status_code == 200
    sources = re.findall(rb'(?:src|href)="([^"]+)"', response.content)
    assert sources and all(not s.startswith((b"http:", b"https:", b"//")) for s in sources), sources


def test_openapi_schema_builds_without_warnings(tmp_path):
    from django.core.management import call_command

    out = tmp_path / "schema.yml"
    call_command("spectacular", "--fail-on-warn", "--validate", "--file", str(out))
    assert "/api/v1/applications/{id}/compare/:" in out.read_text()
