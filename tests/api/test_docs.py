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
