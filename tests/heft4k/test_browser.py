"""The HEFT4K pages in a real browser (system Chromium via Playwright): schedule panel, what-if, apply."""

import os
from pathlib import Path

import pytest

from tests.dashboard.test_browser import browser, log_in, page  # noqa: F401 - fixtures

from .fan import heft4k_schedule

os.environ["DJANGO_ALLOW_ASYNC_UNSAFE"] = "true"
pytestmark = [pytest.mark.browser, pytest.mark.django_db(transaction=True)]
SHOTS = Path(os.environ.get("CONTINUUM_SCREENSHOT_DIR", "/tmp"))


def test_fail_a_node_what_if_then_apply(page, live_server, operator, api, cluster):  # noqa: F811
    from apps.heft4k.models import RemapEvent

    schedule = heft4k_schedule(api, cluster)
    log_in(page, live_server)
    page.goto(f"{live_server.url}/schedules/{schedule.pk}/")
    page.wait_for_selector("#gantt-chart .barlayer .point")
    # Predicted and simulated: every task drawn twice, in two subplots.
    assert page.locator("#gantt-chart .barlayer .point").count() == 2 * schedule.assignments.count()
    assert page.locator("#gantt-chart .colorbar").count() == 1
    box = page.locator("#gantt-chart .barlayer .point").first.bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.wait_for_selector("#gantt-chart .hoverlayer .hovertext")
    assert "niceness:" in page.locator("#gantt-chart .hoverlayer .hovertext").text_content()
    page.screenshot(path=str(SHOTS / "continuum-heft4k-schedule.png"), full_page=True)
    page.mouse.move(0, 0)
    page.locator("#gantt-chart").screenshot(path=str(SHOTS / "continuum-heft4k-gantt.png"))

    page.select_option("#what-if select[name=node]", "node1")
    page.click("#what-if button[type=submit]")
    page.wait_for_selector("#remap-chart .barlayer .point")
    event = RemapEvent.objects.get()
    assert page.inner_text("#remap-status") == "computed, nothing pushed"
    assert page.locator("#remap-changes tbody tr").count() == len(event.moved_tasks) == 4
    page.screenshot(path=str(SHOTS / "continuum-heft4k-remap.png"), full_page=True)
    page.locator("#remap-chart").screenshot(path=str(SHOTS / "continuum-heft4k-remap-gantt.png"))

    page.click("#apply-remap")
    page.wait_for_selector(".message-success")
    assert page.inner_text("#remap-status") == "stored; nothing in Kubernetes to change"
    page.goto(f"{live_server.url}/applications/{schedule.application_id}/")
    page.screenshot(path=str(SHOTS / "continuum-heft4k-application.png"), full_page=True)
    page.goto(f"{live_server.url}/remaps/")
    page.screenshot(path=str(SHOTS / "continuum-heft4k-remaps.png"), full_page=True)
    assert page.errors == [] and page.foreign_requests == []
