"""The dashboard in a real browser: Playwright driving the system Chromium against the live server.

Chromium must be installed (``apt-get install -y chromium``); when it is missing these tests FAIL, they do
not skip, so CI cannot pass without running them. ``playwright install`` cannot download browsers here, so
the system binary is used (``CONTINUUM_CHROMIUM`` overrides its path).
"""

import os
import re
from pathlib import Path

import pytest

from tests.conftest import DATA, make_application, schedule_on_platform

# Playwright's sync API runs an event loop in this thread; Django would refuse ORM calls from it.
os.environ["DJANGO_ALLOW_ASYNC_UNSAFE"] = "true"

pytestmark = [pytest.mark.browser, pytest.mark.django_db(transaction=True)]

CHROMIUM = os.environ.get("CONTINUUM_CHROMIUM", "/usr/bin/chromium")
# Without the networking flags Chromium keeps trying to reach Google services on a closed network.
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
SCREENSHOT = Path(os.environ.get("CONTINUUM_SCREENSHOT_DIR", "/tmp")) / "continuum-gantt.png"
TIMEOUT_MS = 90_000  # generous: pages render slowly on a busy 2-core machine


@pytest.fixture(scope="module")
def browser():
    if not os.path.exists(CHROMIUM):
        pytest.fail(
            f"Chromium not found at {CHROMIUM}: install it (apt-get install -y chromium) or set CONTINUUM_CHROMIUM; "
            "the browser tests must run, not skip"
        )
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, headless=True, args=FLAGS)
        yield browser
        browser.close()


@pytest.fixture
def page(browser, live_server):
    """A fresh browser context that records page errors and every host it talks to."""
    context = browser.new_context(viewport={"width": 1360, "height": 900})
    context.set_default_timeout(TIMEOUT_MS)
    page = context.new_page()
    page.errors = []
    page.foreign_requests = []
    page.on("pageerror", lambda exc: page.errors.append(str(exc)))
    page.on("console", lambda msg: page.errors.append(msg.text) if msg.type == "error" else None)
    page.on(
        "request",
        lambda req: None if req.url.startswith((live_server.url, "data:")) else page.foreign_requests.append(req.url),
    )
    yield page
    context.close()


def log_in(page, live_server, username="operator", password="operator-pass-123"):
    page.goto(live_server.url + "/")
    assert "/login/" in page.url  # the dashboard sends strangers to the login page
    page.fill("#id_username", username)
    page.fill("#id_password", password)
    page.click("button[type=submit]")
    page.wait_for_selector("h1:has-text('Overview')")


def test_upload_schedule_with_heft_and_see_the_gantt_chart(page, live_server, operator, cluster):
    from apps.scheduling.models import Schedule

    log_in(page, live_server)

    # Upload a real workflow (WfCommons Montage, 58 tasks).
    page.click("nav.mainnav >> text=Applications")
    page.set_input_files("input[name=file]", str(DATA / "montage-chameleon-2mass-005d-001.json"))
    page.click("#upload button[type=submit]")
    page.wait_for_selector("text=58 tasks, 114 edges")
    page.wait_for_selector("#dag-chart .scatterlayer .point")
    task_points = page.locator("#dag-chart .scatterlayer .trace").last.locator(".point")
    assert task_points.count() == 58

    # Schedule it with HEFT on the 4-node cluster.
    page.select_option("select[name=algorithm]", "heft")
    page.check("input[name=target][value=cluster]")
    page.select_option("select[name=cluster]", str(cluster.pk))
    page.click("#schedule button[type=submit]")

    # Wait for the job, then follow its result.
    page.wait_for_selector("#job-state:has-text('Succeeded')")
    page.click("#job-result")
    page.wait_for_url(re.compile(r"/schedules/\d+/$"))

    schedule = Schedule.objects.get()
    expected = schedule.assignments.count()
    assert expected == 58
    page.wait_for_selector("#gantt-chart .barlayer .point")
    assert page.locator("#gantt-chart .barlayer .point").count() == expected
    # One row per Ready node, and the critical path has its legend entry.
    ticks = page.locator("#gantt-chart .yaxislayer-above .ytick text").all_text_contents()
    assert sorted(ticks) == ["node0", "node1", "node2", "node3"]
    assert "critical path" in page.locator("#gantt-chart .legend").text_content()
    assert page.locator("table tr.critical").count() == len(
        schedule.to_engine().critical_path(schedule.application.graph, schedule.engine_platform())
    )
    # Hovering a bar shows the task's details.
    # Plotly's drag layer sits on top of the bars and computes hover from the mouse position.
    box = page.locator("#gantt-chart .barlayer .point").first.bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.wait_for_selector("#gantt-chart .hoverlayer .hovertext")
    hover = page.locator("#gantt-chart .hoverlayer .hovertext").text_content()
    assert "start:" in hover and "finish:" in hover and "frame" in hover

    page.screenshot(path=str(SCREENSHOT), full_page=True)
    assert page.errors == []
    assert page.foreign_requests == []  # plotly.js and everything else from our own server


def test_job_page_follows_progress_live(page, live_server, operator, fleet):
    from apps.jobs.models import Job

    app = make_application(fleet)
    platform = {"format": "continuum.platform/v1", "processors": [{"id": f"p{i}"} for i in range(3)]}
    schedule = schedule_on_platform(app, platform)
    job = Job.objects.create(fleet=fleet, kind="schedule", state="running", progress=10, message="ranking tasks")

    log_in(page, live_server)
    page.goto(f"{live_server.url}/jobs/{job.pk}/")
    assert page.inner_text("#job-percent") == "10"

    Job.objects.filter(pk=job.pk).update(progress=60, message="placed 6/10 tasks")
    page.wait_for_selector("#job-message:has-text('placed 6/10 tasks')")
    assert page.inner_text("#job-percent") == "60"
    assert page.get_attribute("#job-bar", "style") == "width: 60%;"

    Job.objects.filter(pk=job.pk).update(
        state="succeeded", progress=100, message="done", result={"schedule": schedule.pk}
    )
    page.wait_for_selector("#job-result")  # the page reloads once the job is done
    assert page.get_attribute("#job-result", "href") == f"/schedules/{schedule.pk}/"
    assert page.inner_text("#job-state") == "Succeeded"
    assert page.errors == []


def test_bad_upload_shows_the_error_in_the_page(page, live_server, operator, tmp_path):
    from apps.workloads.models import Application

    bad = tmp_path / "loop.json"
    bad.write_text(
        '{"format": "continuum.dag/v1", "tasks": [{"id": "a", "cost": {"cpu": 1}}, {"id": "b", "cost": {"cpu": 1}}],'
        ' "edges": [{"src": "a", "dst": "b"}, {"src": "b", "dst": "a"}]}'
    )
    log_in(page, live_server)
    page.goto(live_server.url + "/applications/")
    page.set_input_files("input[name=file]", str(bad))
    page.click("#upload button[type=submit]")
    alert = page.locator(".form-error").first.inner_text()
    assert "Nothing was imported" in alert and "loop.json: the graph has a cycle: a -> b -> a" in alert
    assert Application.objects.count() == 0


COMPARISON_SCREENSHOT = SCREENSHOT.with_name("continuum-comparison.png")


def test_compare_algorithms_and_see_stacked_gantt_charts_on_one_time_axis(page, live_server, operator, fleet):
    from apps.scheduling.models import Comparison

    app = make_application(fleet, "fig31.dag.json")
    log_in(page, live_server)
    page.goto(f"{live_server.url}/applications/{app.pk}/")

    # Compare HEFT, XEFT and G-FL on the thesis' board (1 CPU + 1 GPU sharing memory), 2 frames.
    form = page.locator("#compare form")
    for name in ("visionworks", "gfl_c"):  # checked by default; leave them out
        form.locator(f"input[name=compare-algorithms][value={name}]").uncheck()
    form.locator("input[name=compare-target][value=platform]").check()
    form.locator("input[name=compare-cpus]").fill("1")
    form.locator("input[name=compare-gpus]").fill("1")
    form.locator("input[name=compare-shared_memory]").check()
    form.locator("summary:has-text('Frames')").click()
    form.locator("input[name=compare-frames]").fill("2")
    form.locator("button[type=submit]").click()

    page.wait_for_selector("#job-state:has-text('Succeeded')")
    page.click("#job-result")
    page.wait_for_url(re.compile(r"/comparisons/\d+/$"))
    comparison = Comparison.objects.get()
    assert comparison.algorithms == ["heft", "xeft", "gfl"]

    # Three Gantt charts, one above the other: 3 x 8 tasks x 2 frames bars, one y axis each.
    page.wait_for_selector("#comparison-gantt .barlayer .point")
    assert page.locator("#comparison-gantt .barlayer .point").count() == 3 * 16
    assert page.locator("#comparison-gantt g.cartesianlayer > g.subplot").count() == 3
    titles = page.locator("#comparison-gantt .annotation-text").all_text_contents()
    assert [t.split(":")[0] for t in titles[:3]] == ["HEFT", "XEFT", "GFL"]
    assert "makespan 34" in titles[1]  # XEFT_p, 2 batched frames (spec 01 section 7.5)
    legend = page.locator("#comparison-gantt .legend").text_content()
    assert "frame 0" in legend and "frame 1" in legend and "critical path" in legend

    page.screenshot(path=str(COMPARISON_SCREENSHOT), full_page=True)

    # The time axis is shared: zooming the top chart zooms the others.
    ranges = page.evaluate(
        """() => Plotly.relayout('comparison-gantt', {'xaxis.range': [5, 20]}).then(() => {
            const l = document.getElementById('comparison-gantt')._fullLayout;
            return [l.xaxis.range, l.xaxis2.range, l.xaxis3.range];
        })"""
    )
    assert ranges == [[5, 20], [5, 20], [5, 20]]

    # The figures side by side, and a bar chart of them.
    table = page.locator("#comparison-table").inner_text()
    assert "XEFT" in table and "best" in table
    page.wait_for_selector("#comparison-bars .barlayer .point")
    assert page.locator("#comparison-bars g.cartesianlayer > g.subplot").count() >= 6
    assert page.errors == []
    assert page.foreign_requests == []
