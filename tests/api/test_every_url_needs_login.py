"""Every page and API endpoint refuses anonymous callers (a guard for URLs added later)."""

import re

import pytest
from django.urls import URLPattern, URLResolver, get_resolver

pytestmark = pytest.mark.django_db

PUBLIC = {"login/", "logout/"}


def patterns(resolver=None, prefix=""):
    for entry in (resolver or get_resolver()).url_patterns:
        route = prefix + str(entry.pattern)
        if isinstance(entry, URLResolver):
            if route.startswith("admin/"):
                continue  # Django's admin has its own login
            yield from patterns(entry, route)
        elif isinstance(entry, URLPattern):
            yield route


def concrete(route: str) -> str | None:
    """A URL for ``route`` with 1 for every argument; None for DRF's format-suffix variants."""
    if "format" in route:  # DRF's .json/.api suffix variants of the same views
        return None
    route = re.sub(r"\(\?P<\w+>\[\^/\.\]\+\)", "1", route)  # DRF lookups (pk, slug)
    route = route.replace("^", "").replace("$", "").replace("\\Z", "")
    route = re.sub(r"<(int|slug|str):\w+>", "1", route)
    route = re.sub(r"<uuid:\w+>", "00000000-0000-0000-0000-000000000000", route)
    if "<" in route or "(" in route or "[" in route:
        return None
    return "/" + route


def test_anonymous_callers_are_refused_everywhere(client):
    urls = sorted({u for u in map(concrete, patterns()) if u and u.strip("/") + "/" not in PUBLIC and u != "/"})
    assert len(urls) > 50
    for url in urls:
        response = client.get(url)
        # /metrics does not exist until CONTINUUM_METRICS_TOKEN is set (then 401: tests/api/test_metrics.py).
        refused = (302, 401, 403, 405, 404) if url == "/metrics" else (302, 401, 403, 405)
        assert response.status_code in refused, (url, response.status_code)
        if response.status_code == 302:
            assert response["Location"].startswith("/login/"), (url, response["Location"])
    assert client.get("/").status_code == 302
