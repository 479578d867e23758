"""The Content-Security-Policy in a real browser (system Chromium, fixtures of ``test_browser``): the chart
pages (Plotly), the API docs (Swagger UI, ReDoc) and the admin work under it, with no violation reported.
Issue 25: no policy at all before."""

import os

import pytest

from tests.dashboard.test_browser import browser, log_in, page  # noqa: F401  (fixtures)

os.environ["DJANGO_ALLOW_ASYNC_UNSAFE"] = "true"

pytestmark = [pytest.mark.browser, pytest.mark.django_db(transaction=True)]

#: Collects every violation the page reports, from before its first script runs (DevTools injects it: the
#: policy does not apply to it).
WATCH = """window.__csp = [];
document.addEventListener('securitypolicyviolation',
  e => window.__csp.push(`${e.violatedDirective} ${e.blockedURI} ${e.sourceFile}:${e.lineNumber}`));"""


def violations(page) -> list[str]:  # noqa: F811
    return page.evaluate("window.__csp")


def test_chart_pages_docs_and_admin_work_under_the_policy(page, live_server, operator, schedule):  # noqa: F811
    page.context.add_init_script(WATCH)
    missing = []
    page.on("response", lambda r: missing.append(r.url) if r.status == 404 else None)
    log_in(page, live_server)
    assert violations(page) == []

    response = page.goto(f"{live_server.url}/schedules/{schedule.pk}/")
    assert "script-src 'self'" in response.headers["content-security-policy"]
    page.wait_for_selector("#gantt-chart .barlayer .point")
    box = page.locator("#gantt-chart .barlayer .point").first.bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.wait_for_selector("#gantt-chart .hoverlayer .hovertext")
    # Plotly's own CSS rules reached the sheet the page links for them (no <style> element needed).
    rules = page.evaluate("document.getElementById('plotly.js-style-global').sheet.cssRules.length")
    assert rules > 0
    assert page.locator("#gantt-chart .modebar").count() == 1
    assert page.evaluate("document.querySelectorAll('style').length") == 0
    assert violations(page) == []

    page.goto(f"{live_server.url}/api/docs/")
    page.wait_for_selector(".swagger-ui .opblock", timeout=90_000)
    assert violations(page) == []
    page.goto(f"{live_server.url}/api/redoc/")
    page.wait_for_selector("[role=navigation], .menu-content", timeout=90_000)
    # ReDoc's "powered by" logo comes from its CDN: refused, as every third-party request is meant to be.
    assert [v for v in violations(page) if "https://cdn.redoc.ly/" not in v] == []
    page.evaluate("window.__csp.length = 0")

    operator.is_staff = operator.is_superuser = True
    operator.save()
    page.goto(f"{live_server.url}/admin/clusters/cluster/")
    page.wait_for_selector("#changelist, #content-main")
    assert violations(page) == []
    assert [e for e in page.errors if "cdn.redoc.ly" not in e and "404" not in e] == []
    assert [u for u in missing if not u.endswith("/favicon.ico")] == []  # browsers ask for it unbidden
