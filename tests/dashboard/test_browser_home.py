"""The product explaining itself, in a real browser (system Chromium, fixtures of ``test_browser``): the home
page's paths, a push shown disabled with its reason, a refused form's errors brought to the top, and the
layout at 390 px (a phone) without horizontal overflow."""

import os

import pytest
from django.urls import reverse

from tests.conftest import make_application
from tests.dashboard.test_browser import browser, log_in, page  # noqa: F401  (fixtures)

os.environ["DJANGO_ALLOW_ASYNC_UNSAFE"] = "true"

pytestmark = [pytest.mark.browser, pytest.mark.django_db(transaction=True)]

PHONE = {"width": 390, "height": 844}
#: Generous: the machine that runs the suite may be busy (a wait, not a speed assertion).
TIMEOUT_MS = 90_000


@pytest.fixture
def patient(page):  # noqa: F811
    """``test_browser``'s page with this module's timeout."""
    page.set_default_timeout(TIMEOUT_MS)
    page.set_default_navigation_timeout(TIMEOUT_MS)
    return page


#: The elements that reach past the screen's right edge (tag, id, class, right edge in px).
WIDEST = """[...document.querySelectorAll('body *')]
  .map(e => [e, e.getBoundingClientRect().right])
  .filter(([e, r]) => r > 391)
  .slice(0, 6)
  .map(([e, r]) => `${e.tagName}#${e.id}.${e.className} ${Math.round(r)}`)"""


def test_home_page_leads_to_the_three_paths(patient, live_server, operator):
    log_in(patient, live_server)
    for heading in ("Schedule a DAG on boards or a cluster", "Place a ROS graph", "Real-time and verification"):
        assert patient.locator(f"h2:has-text('{heading}')").is_visible()
    # Nothing uploaded yet: scheduling is disabled, saying why, with the way to fix it.
    blocked = patient.locator("#path-dag button:has-text('Schedule an application')")
    assert blocked.is_disabled()
    assert "no application yet" in patient.locator("#path-dag").inner_text()
    patient.click("#path-dag a:has-text('upload a DAG')")
    patient.wait_for_url("**/applications/#upload")
    assert patient.locator("#upload input[name=file]").is_visible()
    # The API item opens the API's reference, not DRF's browsable root.
    patient.click("nav.mainnav >> text=API")
    patient.wait_for_url("**/api/docs/")


def test_push_is_disabled_with_its_reason(patient, live_server, operator, schedule, cluster):
    from apps.scheduling.models import Schedule

    Schedule.objects.filter(pk=schedule.pk).update(cluster=cluster)
    log_in(patient, live_server)
    patient.goto(live_server.url + reverse("scheduling:schedule", args=[schedule.pk]))
    button = patient.locator("button:has-text('Push to Kubernetes')")
    assert button.is_visible() and button.is_disabled()
    reason = patient.locator("#why-push-to-kubernetes")
    assert f"cluster {cluster.name} has no Kubernetes API configured" in reason.inner_text()
    reason.locator("a").click()
    patient.wait_for_selector("#kubernetes:has-text('Model only')")


def test_refused_form_shows_its_errors_at_the_top_in_view(patient, live_server, operator, fleet):
    app = make_application(fleet, "montage-chameleon-2mass-005d-001.json")
    log_in(patient, live_server)
    patient.goto(live_server.url + reverse("workloads:application", args=[app.pk]))
    patient.check("#schedule input[name=target][value=platform]")
    patient.fill("#schedule input[name=cpus]", "2")
    patient.locator("#schedule details summary:has-text('Parameters')").click()
    patient.fill("#schedule textarea[name=params]", "{oops")
    patient.click("#schedule button[type=submit]")
    summary = patient.locator("#schedule [data-error-summary]")
    summary.wait_for()
    assert "not JSON" in summary.inner_text()
    # Brought into view although the form sits below the task graph.
    box = summary.bounding_box()
    assert 0 <= box["y"] < patient.viewport_size["height"]
    assert patient.evaluate("document.activeElement.hasAttribute('data-error-summary')")
    summary.locator("a[href='#id_params']").click()
    assert patient.evaluate("location.hash") == "#id_params"


def test_phone_layout_has_no_horizontal_overflow(browser, live_server, operator, schedule, cluster):  # noqa: F811
    context = browser.new_context(viewport=PHONE, device_scale_factor=2, is_mobile=True, has_touch=True)
    context.set_default_timeout(TIMEOUT_MS)
    phone = context.new_page()
    try:
        log_in(phone, live_server)
        # The menu collapses behind a button and opens into a usable column.
        nav = phone.locator("nav.mainnav")
        assert not nav.is_visible()
        phone.click("[data-nav-toggle]")
        assert nav.is_visible() and nav.locator("a:has-text('Applications')").bounding_box()["width"] > 200
        urls = [
            reverse("dashboard:home"),
            reverse("clusters:clusters"),
            reverse("clusters:cluster", args=[cluster.pk]),
            reverse("workloads:applications"),
            reverse("workloads:application", args=[schedule.application_id]),
            reverse("scheduling:schedules"),
            reverse("scheduling:schedule", args=[schedule.pk]),
            reverse("scheduling:comparisons"),
            reverse("jobs:jobs"),
            reverse("devices:devices"),
            reverse("containers:rosgraphs"),
            reverse("heft4k:remaps"),
            reverse("realtime:overview"),
            reverse("verification:overview"),
        ]
        widths = {}
        for url in urls:
            phone.goto(live_server.url + url)
            phone.wait_for_load_state("load")
            width = phone.evaluate("document.scrollingElement.scrollWidth")
            if width > PHONE["width"]:  # name what sticks out, for the failure message
                width = (width, phone.evaluate(WIDEST))
            widths[url] = width
        too_wide = {u: w for u, w in widths.items() if not isinstance(w, int)}
        assert not too_wide, too_wide
        # Charts follow the screen's width.
        phone.goto(live_server.url + reverse("scheduling:schedule", args=[schedule.pk]))
        chart = phone.locator(".js-plotly-plot").first
        chart.wait_for()
        assert chart.bounding_box()["width"] <= PHONE["width"]
    finally:
        context.close()


#: The boxes of a figure's legend and of its titles (figure title, subplot titles) that the legend overlaps.
LEGEND_OVERLAPS = """(sel) => {
  const gd = document.querySelector(sel);
  const legend = gd.querySelector('.legend');
  if (!legend) return ['no legend'];
  const l = legend.getBoundingClientRect();
  const titles = [...gd.querySelectorAll('.gtitle, .annotation-text, .xtitle, .xtick text')];
  return titles.map(t => [t.textContent, t.getBoundingClientRect()])
    .filter(([_, r]) => r.width && !(r.right <= l.left || r.left >= l.right || r.bottom <= l.top || r.top >= l.bottom))
    .map(([text, r]) => text);
}"""


def test_phone_legends_do_not_overlap_titles(browser, live_server, operator, fleet):  # noqa: F811
    from apps.jobs.services import start_job
    from apps.scheduling.kinds import SchedulingJob
    from apps.scheduling.models import Comparison

    app = make_application(fleet, "montage-chameleon-2mass-005d-001.json")
    processors = [{"id": "cpu0"}, {"id": "cpu1"}, {"id": "gpu0", "class": "gpu"}]  # Montage: CPU costs only
    platform = {"format": "continuum.platform/v1", "processors": processors}
    args = {"application": app.pk, "algorithms": ["heft", "gfl"], "platform": platform, "frames": 3}
    assert start_job(SchedulingJob.COMPARE, fleet, args, operator).state == "succeeded"
    comparison = Comparison.objects.get()
    schedule = comparison.ordered_schedules()[0]
    context = browser.new_context(viewport=PHONE, is_mobile=True, has_touch=True)
    context.set_default_timeout(TIMEOUT_MS)
    phone = context.new_page()
    try:
        log_in(phone, live_server)
        for url, chart in (
            (reverse("scheduling:comparison", args=[comparison.pk]), "#comparison-gantt"),
            (reverse("scheduling:schedule", args=[schedule.pk]), "#gantt-chart"),
        ):
            phone.goto(live_server.url + url)
            phone.wait_for_selector(f"{chart} .legend")
            phone.wait_for_function(f"document.querySelector('{chart}').dataset.phoneLegend === 'below'")
            assert phone.evaluate(LEGEND_OVERLAPS, chart) == [], url
            # The idle GPU keeps its row in every chart.
            ticks = phone.locator(f"{chart} .yaxislayer-above .ytick text").all_text_contents()
            assert "gpu0" in ticks, (url, ticks)
    finally:
        context.close()
