"""Layouts measured in a real browser at 1440 x 900 and 390 x 844 (issue 30, item 6): the login card is a card,
not a 1,230 px band, and the clustering page's container table does not run under its "Place on a cluster"
card. Bounding boxes of the real pages (system Chromium; fixtures of test_browser.py)."""

import pytest
from django.urls import reverse

from tests.conftest import DATA
from tests.containers.test_pages import cluster_it, make_graph
from tests.dashboard.test_browser import browser, log_in  # noqa: F401 (the browser fixture)

pytestmark = [pytest.mark.browser, pytest.mark.django_db(transaction=True)]

SIZES = [{"width": 1440, "height": 900}, {"width": 390, "height": 844}]
BOX = "(el) => { const r = el.getBoundingClientRect(); return {left: r.left, right: r.right, width: r.width}; }"
#: The visible right edge of a table: its own box clipped by the scrolling box it sits in.
VISIBLE_RIGHT = """(table) => {
  let right = table.getBoundingClientRect().right;
  for (let el = table.parentElement; el; el = el.parentElement) {
    const style = getComputedStyle(el);
    if (style.overflowX !== 'visible') right = Math.min(right, el.getBoundingClientRect().right);
  }
  return right;
}"""


@pytest.mark.parametrize("viewport", SIZES, ids=["1440", "390"])
def test_the_login_card_is_a_card(browser, live_server, viewport):  # noqa: F811
    context = browser.new_context(viewport=viewport)
    try:
        page = context.new_page()
        page.goto(live_server.url + reverse("login"))
        card = page.locator("section.login").evaluate(BOX)
    finally:
        context.close()
    assert card["width"] <= 382, card
    assert card["left"] >= 0 and card["right"] <= viewport["width"], card


@pytest.mark.parametrize("viewport", SIZES, ids=["1440", "390"])
def test_the_clustering_table_stays_clear_of_the_place_card(browser, live_server, operator, fleet, viewport):  # noqa: F811
    row = make_graph(fleet, (DATA / "autoware_reference_system.json").read_bytes())
    clustering = cluster_it(row)
    context = browser.new_context(viewport=viewport)
    try:
        page = context.new_page()
        page.set_default_timeout(90_000)
        log_in(page, live_server)
        page.goto(live_server.url + reverse("containers:clustering", args=[clustering.pk]))
        table = page.locator("section.grow table.table").first
        visible_right = table.evaluate(VISIBLE_RIGHT)
        side = page.locator("#place").evaluate(BOX)
        width = page.evaluate("() => document.scrollingElement.scrollWidth")
    finally:
        context.close()
    if viewport["width"] >= 1000:  # side by side: the table ends before the card starts
        assert visible_right <= side["left"] + 1, (visible_right, side)
    assert width <= viewport["width"] + 1  # no sideways page scroll on a phone either
