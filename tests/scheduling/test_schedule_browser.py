"""A 1000-task schedule page in a real browser (Playwright, system Chromium; see tests/dashboard/test_browser.py):
its WebGL Gantt draws every bar and hovers with the bar's own task, processor, frame, start, finish and
duration with units; the assignment table shows one page and pages and filters through the query string."""

import re

import pytest
from django.db import transaction

from apps.scheduling.models import Schedule
from apps.ui import charts
from apps.workloads.models import Application
from continuum.engine.device import algorithms
from continuum.engine.device.generators import layered_dag, related_platform
from tests.dashboard.test_browser import browser, log_in, page  # noqa: F401 (the browser fixtures)

pytestmark = [pytest.mark.browser, pytest.mark.django_db(transaction=True)]
SLOW_MS = 120_000

#: The centre of bar ``k`` of the first trace, in page pixels, and its task and frame, from Plotly's own axes.
BAR_CENTRE = """(k) => {
  const gd = document.getElementById('gantt-chart');
  const g = JSON.parse(gd.data[0].meta.gantt);
  const xa = gd._fullLayout.xaxis, ya = gd._fullLayout.yaxis, box = gd.getBoundingClientRect();
  const mid = (g.start[k] + g.finish[k]) / 2, row = g.rows[g.row[k]];
  return {task: g.task[k], frame: g.frame[k], x: box.left + xa._offset + xa.l2p(mid),
          y: box.top + ya._offset + ya.l2p(ya.d2l(row)), bars: g.task.length};
}"""

ZOOM = """(k) => {
  const gd = document.getElementById('gantt-chart');
  const g = JSON.parse(gd.data[0].meta.gantt), d = g.finish[k] - g.start[k];
  return Plotly.relayout(gd, {'xaxis.range': [g.start[k] - 2 * d, g.finish[k] + 2 * d]}).then(() => null);
}"""


@pytest.fixture
def big_schedule(fleet):
    platform = related_platform(4, seed=1)
    dag = layered_dag(1000, seed=4, processors=4)
    app = Application(fleet=fleet, name="layered-1000")
    app.set_graph(dag)
    app.save()
    result = algorithms.run("heft", dag, platform, frames=3)  # 3000 bars: past WEBGL_BARS
    with transaction.atomic():
        return Schedule.store(result, application=app, platform=platform)


def test_a_1000_task_schedule_page_hovers_right_and_pages_and_filters_its_table(
    page,  # noqa: F811
    live_server,
    operator,
    big_schedule,
):
    # A loaded CI machine serves plotly.js (4.8 MB) and this page slowly: generous timeouts, no speed asserted.
    page.set_default_timeout(SLOW_MS)
    log_in(page, live_server)
    url = f"{live_server.url}/schedules/{big_schedule.pk}/"
    page.goto(url)
    # The facts are expanded into points in the browser: every bar of every trace gets its 4 points.
    page.wait_for_function(
        "() => { const gd = document.getElementById('gantt-chart');"
        " return gd && gd.data && gd.data.length && gd.data.every(t => !(t.meta && t.meta.gantt) || t.x.length > 0); }"
    )
    total = page.evaluate(
        "() => document.getElementById('gantt-chart').data"
        ".filter(t => t.meta && t.meta.gantt).reduce((n, t) => n + t.x.length / 4, 0)"
    )
    assert total == 3000
    assert page.locator("#gantt-chart canvas").count() > 0  # drawn with WebGL

    unit = big_schedule.application.graph.time_unit
    rows = {(a.task, a.frame): a for a in big_schedule.assignments.all()}
    for k in (0, 400):
        # Zoom on the bar as an operator would (at full width a bar is a few pixels wide), then hover it.
        page.evaluate(ZOOM, k)
        bar = page.evaluate(BAR_CENTRE, k)
        page.mouse.move(bar["x"] - 2, bar["y"])
        page.mouse.move(bar["x"], bar["y"])
        page.wait_for_selector("#gantt-chart .hoverlayer .hovertext")
        hover = page.locator("#gantt-chart .hoverlayer .hovertext").text_content()
        a = rows[(bar["task"], bar["frame"])]
        for line in (
            f"{a.task} (frame {a.frame})",
            f"processor: {a.processor}",
            f"start: {charts.fmt(a.start)} {unit}",
            f"finish: {charts.fmt(a.finish)} {unit}",
            f"duration: {charts.fmt(a.finish - a.start)} {unit}",
        ):
            assert line in hover, (line, hover)

    # One page of the table, then the next.
    table = page.locator("#assignment-table tbody tr")
    assert table.count() == 100
    ordered = list(big_schedule.assignments.values_list("task", "frame", "processor"))
    page.click("nav[aria-label='assignment pages'] a[rel=next]")
    page.wait_for_url(re.compile(r"page=2"))
    first = page.locator("#assignment-table tbody tr").first.locator("td")
    assert (first.nth(0).text_content().split()[0], int(first.nth(1).text_content())) == ordered[100][:2]

    # Filter by processor and frame: every row matches and the count is the database's.
    page.select_option("#assignment-filter select[name=processor]", "p1")
    page.select_option("#assignment-filter select[name=frame]", "2")
    page.click("#assignment-filter button[type=submit]")
    page.wait_for_url(re.compile(r"processor=p1&frame=2"))
    expected = big_schedule.assignments.filter(processor="p1", frame=2).count()
    assert page.locator("#assignments h2 .count").text_content().startswith(f"{expected} of 3000")
    cells = page.locator("#assignment-table tbody tr").evaluate_all(
        "rows => rows.map(r => [r.cells[1].textContent.trim(), r.cells[2].textContent.trim()])"
    )
    assert cells and len(cells) == min(expected, 100) and all(c == ["2", "p1"] for c in cells)
    assert page.errors == []
    assert page.foreign_requests == []
