"""The operator's whole flow at 1000-task scale in a real browser (Playwright, system Chromium; fixtures in
tests/dashboard/test_browser.py) with a real Celery worker (tests/services): upload a generated 1000-task DAG
file, schedule it from its page (the form's defaults, 10 frames), follow the job's progress without a reload,
hover the WebGL Gantt (checked against the stored rows), see "Push to Kubernetes" disabled with its reason and
the link to fix it, cancel a larger job and retry it to completion, and the same pages at 390 px wide without
horizontal overflow (issue 13, "Done means")."""

import json
import re
from pathlib import Path

import pytest

from apps.jobs.models import Job
from apps.scheduling.models import Schedule
from apps.ui import charts
from apps.workloads.models import Application
from continuum.engine.device.generators import layered_dag
from tests.dashboard.test_browser import browser, log_in  # noqa: F401 (the browser fixture)
from tests.scheduling.test_schedule_browser import BAR_CENTRE, ZOOM
from tests.services.conftest import celery_broker, redis_url, start_worker  # noqa: F401 (the worker fixtures)

pytestmark = [pytest.mark.browser, pytest.mark.services, pytest.mark.django_db(transaction=True)]

#: Generous: a busy 2-core CI machine renders a 10,000-bar page and runs the jobs in seconds, not milliseconds.
SLOW_MS = 240_000
TASKS, FRAMES = 1000, 10
#: The larger job: 16 model CPUs x 100 frames (100,000 placements) runs long enough to be cancelled mid-way.
BIG_CPUS, BIG_FRAMES = 16, 100
PHONE = {"width": 390, "height": 844}
SHOTS = Path("/tmp")

#: Every state and percent the job page shows, reported from the page to the test through a binding, with the
#: page load it was shown in (a reload starts a new load id: what changed without one is the live view).
RECORD_PROGRESS = """() => {
  const load = Math.random().toString(36).slice(2);
  const report = () => {
    const state = document.getElementById('job-state'), percent = document.getElementById('job-percent');
    if (state && percent) window.recordProgress(load, state.textContent.trim(), Number(percent.textContent));
  };
  document.addEventListener('DOMContentLoaded', () => {
    report();
    const box = document.getElementById('job-progress');
    if (box) new MutationObserver(report).observe(box, {subtree: true, childList: true, characterData: true});
  });
}"""

#: Bars of the first trace to hover, near its start, middle and end: ones at least a millisecond long (a
#: layered DAG draws some costs near 0, bars no operator could point at, whose start and finish round alike).
HOVERABLE = """() => {
  const g = JSON.parse(document.getElementById('gantt-chart').data[0].meta.gantt), n = g.task.length;
  const from = (k) => { while (g.finish[k] - g.start[k] < 1) k = (k + 1) % n; return k; };
  return [from(0), from(Math.floor(n / 2)), from(n - 20)];
}"""

OVERFLOW = "() => document.scrollingElement.scrollWidth"


@pytest.fixture
def dag_file(tmp_path) -> Path:
    """A 1000-task layered DAG of the HEFT literature (seeded: the same file every run), as continuum JSON."""
    path = tmp_path / "layered-1000.json"
    path.write_text(json.dumps(layered_dag(TASKS, seed=13).to_dict()))
    return path


def follow_progress(page) -> list[tuple[str, str, int]]:
    """Record (load id, state, percent) each time the job page shows a new one."""
    seen: list[tuple[str, str, int]] = []

    def record(_source, load, state, percent):
        if not seen or seen[-1] != (load, state, percent):
            seen.append((load, state, percent))

    page.expose_binding("recordProgress", record)
    page.add_init_script(f"({RECORD_PROGRESS})()")
    return seen


def live_changes(seen: list[tuple[str, str, int]]) -> list[tuple[str, int]]:
    """What one page load showed, for the load that showed the most (the live view, before its final reload)."""
    loads: dict[str, list[tuple[str, int]]] = {}
    for load, state, percent in seen:
        loads.setdefault(load, []).append((state, percent))
    return max(loads.values(), key=len)


def job_of(page) -> Job:
    return Job.objects.get(pk=re.search(r"/jobs/([0-9a-f-]+)/$", page.url).group(1))


def schedule_from_the_application_page(page, url: str, **fields) -> Job:
    """Submit the schedule form of the application page at ``url`` with ``fields`` changed (the rest as the
    form offers)."""
    page.goto(url + "#schedule")
    form = page.locator("#schedule form")
    if fields.get("target"):
        form.locator(f"input[name=target][value={fields['target']}]").check()
    if fields.get("cpus") is not None:
        form.locator("input[name=cpus]").fill(str(fields["cpus"]))
    form.locator("details.frames summary").click()
    form.locator("input[name=frames]").fill(str(fields["frames"]))
    form.locator("button[type=submit]").click()
    page.wait_for_url(re.compile(r"/jobs/[0-9a-f-]+/$"))
    return job_of(page)


def hover_text(page, bar: dict, first_line: str) -> str:
    """The Gantt's hover label with the mouse on ``bar``'s centre. Plotly updates the label asynchronously
    (throttled, after a relayout): wait until it names ``first_line`` or give the last one seen."""
    text = ""
    for _ in range(20):
        page.mouse.move(bar["x"] - 2, bar["y"])
        page.mouse.move(bar["x"], bar["y"])
        label = page.locator("#gantt-chart .hoverlayer .hovertext")
        label.first.wait_for()
        text = label.first.text_content()
        if first_line in text:
            break
        page.wait_for_timeout(500)
    return text


def no_horizontal_overflow(page, url: str, name: str) -> None:
    page.goto(url)
    page.wait_for_load_state("load")
    page.screenshot(path=str(SHOTS / f"continuum-flow-phone-{name}.png"), full_page=True)
    page.screenshot(path=str(SHOTS / f"continuum-flow-phone-{name}-top.png"))
    for part in ("#gantt-chart", "#assignments", "#job-arguments", "#schedule"):
        if page.locator(part).count():
            page.locator(part).first.screenshot(path=str(SHOTS / f"continuum-flow-phone-{name}-{part[1:]}.png"))
    width = page.evaluate(OVERFLOW)
    assert width <= PHONE["width"], f"{name} page is {width} px wide at {PHONE['width']} px"


def test_the_operators_flow_at_1000_tasks(browser, live_server, operator, fleet, cluster, dag_file, start_worker):  # noqa: F811
    context = browser.new_context(viewport={"width": 1360, "height": 900}, base_url=live_server.url)
    context.set_default_timeout(SLOW_MS)
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.on("console", lambda msg: errors.append(msg.text) if msg.type == "error" else None)
    seen = follow_progress(page)
    log_in(page, live_server)

    # The whole main menu fits a 1360-px window (no entry cut off behind the bar's hidden scrollbar).
    assert page.evaluate(
        "() => { const n = document.getElementById('mainnav'); return n.scrollWidth <= n.clientWidth; }"
    )

    # 1. Upload the generated file through the upload form.
    page.click("nav.mainnav >> text=Applications")
    page.set_input_files("#upload input[name=file]", str(dag_file))
    page.click("#upload button[type=submit]")
    page.wait_for_url(re.compile(r"/applications/\d+/$"))
    app = Application.objects.get(fleet=fleet)
    assert app.task_count == TASKS and app.name == "layered-1000-13"
    app_url = page.url
    page.wait_for_selector(f"text=Imported 'layered-1000-13': {TASKS} tasks, {app.edge_count} edges.")
    page.wait_for_selector("#dag-chart .main-svg")
    page.screenshot(path=str(SHOTS / "continuum-flow-application.png"), full_page=True)

    # 2. Schedule it with the form's defaults (HEFT on the fleet's only cluster, preselected) for 10 frames; the
    # page answers at once with the queued job, and no worker runs yet.
    assert page.locator("#schedule select[name=algorithm]").input_value() == "heft"
    assert page.locator("#schedule input[name=target][value=cluster]").is_checked()
    assert page.locator("#schedule select[name=cluster]").input_value() == str(cluster.pk)
    job = schedule_from_the_application_page(page, app_url, frames=FRAMES)
    assert job.state == Job.State.PENDING and job.arguments["cluster"] == cluster.pk
    assert job.arguments["params"]["frames"] == FRAMES
    page.wait_for_selector("#job-state:has-text('Pending')")

    # 3. The worker takes it; the page follows without a reload and reloads once at the end to link the result.
    start_worker()
    page.wait_for_selector("#job-result", timeout=SLOW_MS)
    shown = live_changes(seen)
    assert shown[0] == ("Pending", 0), shown
    assert len({percent for _, percent in shown}) >= 2, shown  # the bar moved in the same page
    assert [s for s, _ in shown if s != "Pending"][-1] == "Succeeded", shown
    assert {s for s, _ in shown} <= {"Pending", "Running", "Succeeded"}, shown
    schedule = Schedule.objects.get(job=job)
    assert schedule.cluster_id == cluster.pk and schedule.assignments.count() == TASKS * FRAMES
    page.screenshot(path=str(SHOTS / "continuum-flow-job.png"), full_page=True)

    # 4. The schedule page: its WebGL Gantt hovers with the stored row's task, processor, times and frame.
    page.click("#job-result")
    page.wait_for_url(re.compile(rf"/schedules/{schedule.pk}/$"))
    page.wait_for_function(
        "() => { const gd = document.getElementById('gantt-chart');"
        " return gd && gd.data && gd.data.length && gd.data.every(t => !(t.meta && t.meta.gantt) || t.x.length > 0); }"
    )
    assert page.locator("#gantt-chart canvas").count() > 0  # 10,000 bars: drawn with WebGL
    page.screenshot(path=str(SHOTS / "continuum-flow-schedule.png"), full_page=True)
    unit = app.graph.time_unit
    rows = {(a.task, a.frame): a for a in schedule.assignments.all()}
    for k in page.evaluate(HOVERABLE):
        page.evaluate(ZOOM, k)
        bar = page.evaluate(BAR_CENTRE, k)
        a = rows[(bar["task"], bar["frame"])]
        hover = hover_text(page, bar, f"{a.task} (frame {a.frame})")
        for line in (
            f"{a.task} (frame {a.frame})",
            f"processor: {a.processor}",
            f"start: {charts.fmt(a.start)} {unit}",
            f"finish: {charts.fmt(a.finish)} {unit}",
            f"duration: {charts.fmt(a.finish - a.start)} {unit}",
        ):
            assert line in hover, (line, hover, bar, [a.start, a.finish])
    page.screenshot(path=str(SHOTS / "continuum-flow-gantt-hover.png"))

    # 5. Push to Kubernetes: shown disabled, with why and a link to what fixes it.
    push = page.locator(".action-disabled button:has-text('Push to Kubernetes')")
    assert push.is_disabled()
    reason = page.locator("#why-push-to-kubernetes")
    assert f"cluster {cluster.name} has no Kubernetes API configured" in reason.text_content()
    reason.locator("a:has-text('connect it')").click()
    page.wait_for_url(re.compile(rf"/clusters/{cluster.pk}/#kubernetes$"))
    assert page.locator("#kubernetes").is_visible()

    # 6. A larger job (16 model CPUs, 100 frames): cancelled from its page while it runs, then retried to the end.
    big = schedule_from_the_application_page(page, app_url, target="platform", cpus=BIG_CPUS, frames=BIG_FRAMES)
    page.wait_for_function(
        "() => document.getElementById('job-state').textContent.trim() === 'Running'"
        " && Number(document.getElementById('job-percent').textContent) > 1",
        timeout=SLOW_MS,
    )
    page.click("#job-cancel")
    page.wait_for_selector("#job-progress[data-done=true] #job-state:has-text('Cancelled')", timeout=SLOW_MS)
    assert "cancel asked by operator" in page.inner_text("#job-log")
    assert page.locator("#job-cancel").is_disabled()
    assert not Schedule.objects.filter(job=big).exists()  # nothing half stored
    seen.clear()
    page.click("#job-retry")
    page.wait_for_url(re.compile(r"/jobs/[0-9a-f-]+/$"))
    again = job_of(page)
    assert again.retry_of_id == big.pk and again.arguments == big.arguments
    page.wait_for_selector("#job-result", timeout=SLOW_MS)
    shown = live_changes(seen)
    running = [percent for state, percent in shown if state == "Running"]
    # The bar moved forward several times in one page load: live, not reloaded.
    assert len(set(running)) >= 2 and running == sorted(running) and running[-1] < 100, shown
    retried = Schedule.objects.get(job=again)
    assert retried.cluster_id is None and retried.assignments.count() == TASKS * BIG_FRAMES
    assert page.get_attribute("#job-result", "href") == f"/schedules/{retried.pk}/"
    assert errors == []
    context.close()

    # 7. At 390 px: the application, schedule and job pages fit the screen (tables scroll inside their box).
    phone = browser.new_context(viewport=PHONE, base_url=live_server.url, is_mobile=True, has_touch=True)
    phone.set_default_timeout(SLOW_MS)
    small = phone.new_page()
    log_in(small, live_server)
    no_horizontal_overflow(small, f"{live_server.url}/applications/{app.pk}/", "application")
    no_horizontal_overflow(small, f"{live_server.url}/schedules/{schedule.pk}/", "schedule")
    no_horizontal_overflow(small, f"{live_server.url}/jobs/{job.pk}/", "job")
    phone.close()
