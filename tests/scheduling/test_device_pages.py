"""Dashboard pages of device-level scheduling: every import format, generated DAGs, frames, comparisons, the
UMA advisor, and the chart functions behind them."""

import json

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile
from django.urls import reverse

from apps.devices import charts as device_charts
from apps.jobs.models import Job
from apps.jobs.services import start_job
from apps.scheduling import charts as scheduling_charts
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.models import Comparison, Schedule
from apps.ui import charts
from apps.workloads.models import Application
from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.schedule import Assignment
from continuum.engine.core.schedule import Schedule as EngineSchedule
from continuum.engine.device.board import board
from continuum.engine.device.compare import compare
from continuum.engine.device.pipeline import pipeline
from tests.conftest import DATA, make_application

pytestmark = pytest.mark.django_db

BOARD_FORM = {"target": "platform", "cpus": 1, "gpus": 1, "shared_memory": "on"}


def upload(client, filename, content, **fields):
    if isinstance(content, str):
        content = content.encode()
    return client.post(reverse("workloads:applications"), {"file": SimpleUploadedFile(filename, content), **fields})


@pytest.fixture
def fig31(fleet):
    return make_application(fleet, "fig31.dag.json")


@pytest.fixture
def comparison(fig31):
    job = start_job(
        SchedulingJob.COMPARE,
        fig31.fleet,
        {"application": fig31.pk, "algorithms": ["heft", "xeft"], "platform": board(1).to_dict(), "frames": 2},
    )
    assert job.state == "succeeded", job.error
    return Comparison.objects.get(job=job)


@pytest.fixture
def foreign_comparison(fleets):
    app = make_application(fleets[1], "fig31.dag.json")
    arguments = {"application": app.pk, "algorithms": ["heft"], "platform": board(1).to_dict()}
    job = start_job(SchedulingJob.COMPARE, fleets[1], arguments)
    return Comparison.objects.get(job=job)


# ---- login and scoping ---------------------------------------------------------------------------------
def test_new_pages_require_login(client, fig31, comparison):
    urls = [
        reverse("scheduling:comparisons"),
        reverse("scheduling:comparison", args=[comparison.pk]),
        reverse("devices:devices"),
        reverse("devices:device", args=["jetson-tx2"]),
    ]
    for url in urls:
        response = client.get(url)
        assert response.status_code == 302 and response["Location"].startswith(reverse("login")), url
    posts = [
        (reverse("workloads:application-generate"), {"generator": "thesis"}),
        (reverse("scheduling:application-compare", args=[fig31.pk]), {"compare-algorithms": ["heft"]}),
        (reverse("devices:device", args=["jetson-tx2"]), {"cpu_usage": 1, "gpu_usage": 1}),
    ]
    before = (Application.objects.count(), Job.objects.count())
    for url, data in posts:
        response = client.post(url, data)
        assert response.status_code == 302 and response["Location"].startswith(reverse("login")), url
    assert (Application.objects.count(), Job.objects.count()) == before


def test_new_pages_render_for_a_member(member, comparison):
    for url in [
        reverse("scheduling:comparisons"),
        reverse("scheduling:comparison", args=[comparison.pk]),
        reverse("devices:devices"),
        reverse("devices:device", args=["jetson-agx-xavier"]),
    ]:
        response = member.get(url)
        assert response.status_code == 200, url
        body = response.content.decode()
        assert 'href="/comparisons/"' in body and 'href="/devices/"' in body  # the nav entries


def test_other_fleets_comparisons_answer_404_and_are_not_listed(member, foreign_comparison, comparison):
    assert member.get(reverse("scheduling:comparison", args=[foreign_comparison.pk])).status_code == 404
    url = reverse("scheduling:application-compare", args=[foreign_comparison.application_id])
    jobs = Job.objects.count()
    assert member.post(url, {"compare-algorithms": ["heft"], **_prefixed(BOARD_FORM)}).status_code == 404
    assert Job.objects.count() == jobs
    listing = member.get(reverse("scheduling:comparisons")).content.decode()
    assert f'href="/comparisons/{comparison.pk}/"' in listing
    assert f'href="/comparisons/{foreign_comparison.pk}/"' not in listing


def test_unknown_device_is_404(member):
    assert member.get(reverse("devices:device", args=["jetson-orin"])).status_code == 404


# ---- import and generate --------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("filename", "fmt", "tasks"),
    [("diamond.dax", "dax", 4), ("robot.stg", "stg", 90), ("orb_graph.csv", "thesis_csv", None)],
)
def test_upload_picks_the_format_from_the_file_name(member, filename, fmt, tasks):
    response = upload(member, filename, (DATA / filename).read_bytes())
    app = Application.objects.get()
    assert response.status_code == 302 and app.source_format == fmt
    if tasks:
        assert app.task_count == tasks


def test_upload_stg_with_its_options(member):
    upload(member, "robot.stg", (DATA / "robot.stg").read_bytes(), ccr=2, processors=3, heterogeneity=1, seed=5)
    dag = Application.objects.get().graph
    assert all(set(t.cost) == {"p0", "p1", "p2"} for t in dag.tasks.values())
    assert dag.meta["ccr"] == 2 and any(e.data > 0 for e in dag.edges)


@pytest.mark.parametrize(
    ("filename", "content", "fields", "message"),
    [
        ("bad.stg", "2\n0 0 0\n1 x 1 0\n2 1 1 0\n3 0 1 2\n", {}, "bad.stg: STG line 3: non-integer field"),
        ("bad.dax", "<adag><job id='a'>\n<uses</adag>", {}, "bad.dax: DAX: malformed XML at line 2"),
        ("d.dax", (DATA / "diamond.dax").read_text(), {"ccr": 1}, "STG options: the dax reader has no option"),
        ("r.stg", (DATA / "robot.stg").read_text(), {"heterogeneity": 3}, "less than or equal to 2"),
    ],
)
def test_bad_upload_names_line_or_option_and_stores_nothing(member, filename, content, fields, message):
    response = upload(member, filename, content, **fields)
    assert response.status_code == 400
    assert message in response.content.decode().replace("&#x27;", "'")
    assert Application.objects.count() == 0


def test_generate_a_thesis_dag(member):
    response = member.post(
        reverse("workloads:application-generate"), {"generator": "thesis", "n": 30, "seed": 4, "dag_class": "linear"}
    )
    app = Application.objects.get()
    assert response.status_code == 302 and response["Location"] == reverse("workloads:application", args=[app.pk])
    assert (app.task_count, app.source_format, app.dag["meta"]["shape"]) == (30, "generator:thesis", "linear")
    assert all(set(t["cost"]) <= {"cpu", "gpu"} for t in app.dag["tasks"])


def test_generate_a_layered_dag(member):
    data = {"generator": "layered", "n": 50, "seed": 1, "ccr": 1, "processors": 2, "heterogeneity": 0.5}
    assert member.post(reverse("workloads:application-generate"), data).status_code == 302
    assert Application.objects.get().graph.tasks["0"].cost.keys() == {"p0", "p1"}


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"generator": "thesis", "ccr": 1}, "the layered generator&#x27;s"),
        ({"generator": "layered", "dag_class": "tree"}, "the thesis generator&#x27;s"),
        ({"generator": "layered", "n": 1}, "greater than or equal to 2"),
        ({"generator": "fractal"}, "Select a valid choice"),
    ],
)
def test_bad_generate_requests_show_the_error(member, data, message):
    response = member.post(reverse("workloads:application-generate"), {"seed": 0, **data})
    assert response.status_code == 400 and message in response.content.decode()
    assert Application.objects.count() == 0


# ---- frames -------------------------------------------------------------------------------------------------
def test_schedule_form_with_frames_and_the_figures_on_the_schedule_page(member, fig31):
    response = member.post(
        reverse("scheduling:application-schedule", args=[fig31.pk]),
        {"algorithm": "xeft", **BOARD_FORM, "frames": 3, "period": 10},
    )
    job = Job.objects.get()
    assert response.status_code == 302 and job.state == "succeeded", job.error
    schedule = Schedule.objects.get(job=job)
    assert schedule.params["frames"] == 3 and schedule.params["period"] == 10
    assert [p["id"] for p in schedule.platform["processors"]] == ["cpu0", "gpu0"]
    assert schedule.assignments.count() == 24
    page = member.get(reverse("scheduling:schedule", args=[schedule.pk])).content.decode()
    for label in ("Mean frame latency", "Throughput", "Frame buffers used", "Idle time", "Exclusive overlap XO(A)"):
        assert label in page, label
    assert 'id="idle-table"' in page and "<td>gpu0</td>" in page
    assert '"name":"frame 2"' in page  # the Gantt chart colours bars by frame


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"frames": 2, "fps": 30, "period": 5}, "give either FPS or a period"),
        ({"frames": 0}, "greater than or equal to 1"),
        ({"frames": 2, "params": '{"frames": 3}'}, "frames is given both as a field and in the parameters"),
    ],
)
def test_bad_frame_options_are_shown_and_start_no_job(member, fig31, data, message):
    response = member.post(
        reverse("scheduling:application-schedule", args=[fig31.pk]), {"algorithm": "heft", **BOARD_FORM, **data}
    )
    assert response.status_code == 400 and message in response.content.decode()
    assert not Job.objects.exists()


# ---- comparison ---------------------------------------------------------------------------------------------
def _prefixed(data: dict) -> dict:
    return {f"compare-{k}": v for k, v in data.items()}


def test_compare_form_runs_a_comparison_job_and_the_page_shows_it(member, fig31):
    response = member.post(
        reverse("scheduling:application-compare", args=[fig31.pk]),
        {"compare-algorithms": ["xeft", "heft", "gfl"], "compare-rank_mode": "max", **_prefixed(BOARD_FORM)},
    )
    job = Job.objects.get(kind="compare")
    assert response.status_code == 302 and response["Location"] == reverse("jobs:job", args=[job.pk])
    comparison = Comparison.objects.get(job=job)
    assert comparison.algorithms == ["heft", "xeft", "gfl"]  # in the registry's order
    job_page = member.get(response["Location"]).content.decode()
    assert reverse("scheduling:comparison", args=[comparison.pk]) in job_page
    page = member.get(reverse("scheduling:comparison", args=[comparison.pk])).content.decode()
    assert 'id="comparison-gantt"' in page and 'id="comparison-bars"' in page and 'id="comparison-table"' in page
    assert "HEFT vs XEFT vs GFL" in page
    for schedule in comparison.schedules.all():  # each algorithm links to its own schedule page
        assert reverse("scheduling:schedule", args=[schedule.pk]) in page
    assert '<span class="badge ok">best</span>' in page and "41.4 %" in page  # XEFT vs VisionWorks
    application_page = member.get(reverse("workloads:application", args=[fig31.pk])).content.decode()
    assert reverse("scheduling:comparison", args=[comparison.pk]) in application_page


def test_compare_form_needs_an_algorithm(member, fig31):
    url = reverse("scheduling:application-compare", args=[fig31.pk])
    response = member.post(url, {"compare-rank_mode": "max", **_prefixed(BOARD_FORM)})
    assert response.status_code == 400 and "This field is required" in response.content.decode()
    response = member.post(url, {"compare-algorithms": ["nope"], **_prefixed(BOARD_FORM)})
    assert response.status_code == 400 and "Select a valid choice" in response.content.decode()
    assert not Job.objects.exists()


# ---- devices --------------------------------------------------------------------------------------------------
def test_device_page_advises_zero_copy_for_shwfs_on_xavier(member):
    response = member.post(
        reverse("devices:device", args=["jetson-agx-xavier"]),
        {"cpu_usage": 6.1, "gpu_usage": 7.0, "current_model": "SC", "kernel_time": 41.24, "copy_time": 16.88,
         "cpu_workers": 1, "gpu_workers": 1},
    )  # fmt: skip
    assert response.status_code == 200
    body = response.content.decode()
    assert '<p class="recommendation" id="recommendation">ZC</p>' in body
    assert "1.693\u00d7" in body and "+69.3 %" in body
    assert "ROS-SHM-ZC over a topic" in body and 'id="zone-chart"' in body


def test_device_page_shows_bad_profiles(member):
    url = reverse("devices:device", args=["jetson-tx2"])
    response = member.post(url, {"gpu_usage": 3, "current_model": "SC", "cpu_workers": 1, "gpu_workers": 1})
    assert (
        response.status_code == 400 and "give cpu_usage, or miss_rate_l1 and miss_rate_ll" in response.content.decode()
    )
    response = member.post(url, {"cpu_usage": 3, "gpu_usage": 3, "miss_rate_l1": 2, "cpu_workers": 1, "gpu_workers": 1})
    assert response.status_code == 400 and "less than or equal to 1" in response.content.decode()


# ---- chart functions ------------------------------------------------------------------------------------------
@pytest.fixture
def fig31_dag():
    return TaskGraph.from_dict(json.loads((DATA / "fig31.dag.json").read_text()))


def test_comparison_figure_stacks_one_chart_per_algorithm_on_a_shared_time_axis(fig31_dag):
    platform = board(1)
    made = {}
    compare(fig31_dag, platform, ["heft", "xeft", "gfl"], frames=2, on_schedule=made.__setitem__)
    schedules = [(name, made[name]) for name in ("heft", "xeft", "gfl")]
    fig = scheduling_charts.comparison_figure(schedules, platform=platform, dag=fig31_dag)
    layout = fig.layout
    # Three y axes, one per algorithm, stacked; three x axes bound together.
    assert layout.yaxis.domain[0] > layout.yaxis2.domain[1] and layout.yaxis2.domain[0] > layout.yaxis3.domain[1]
    # make_subplots(shared_xaxes=True): the upper axes follow the bottom one, which alone shows its ticks.
    assert (layout.xaxis.matches, layout.xaxis2.matches, layout.xaxis3.matches) == ("x3", "x3", None)
    assert layout.xaxis.showticklabels is False and layout.xaxis2.showticklabels is False
    assert layout.xaxis3.title.text == "time (ms)" and tuple(layout.xaxis3.range) == pytest.approx((0, 50 * 1.03))
    # Every assignment drawn once, in the subplot of its algorithm.
    for i, (_, schedule) in enumerate(schedules, start=1):
        axis = "y" if i == 1 else f"y{i}"
        drawn = [t for t in fig.data if t.type == "bar" and t.yaxis == axis]
        assert sum(len(t.x) for t in drawn) == len(schedule.assignments) == 16
    titles = [a.text for a in layout.annotations]
    assert titles[:3] == ["HEFT: makespan 50 ms", "XEFT: makespan 34 ms", "GFL: makespan 44 ms"]
    # Frames coloured the same in every chart, each legend entry shown once.
    frame1 = [t for t in fig.data if t.name == "frame 1"]
    assert len(frame1) == 3 and {t.marker.color for t in frame1} == {charts.FRAME_COLOURS[1]}
    assert [t.showlegend for t in frame1] == [True, False, False]
    assert next(t.showlegend for t in fig.data if t.name == "critical path") is True


def test_gantt_colours_frames_and_keeps_the_critical_path(fig31_dag):
    platform = board(1)
    schedule = pipeline("xeft", fig31_dag, platform, frames=3)
    fig = charts.gantt_figure(schedule, platform=platform, dag=fig31_dag)
    names = [t.name for t in fig.data if t.type == "bar"]
    assert names[:3] == ["frame 0", "frame 1", "frame 2"] and names[-1] == "critical path"
    path = set(schedule.critical_path(fig31_dag, platform))
    critical = next(t for t in fig.data if t.name == "critical path")
    assert {(c[0], c[1]) for c in critical.customdata} == path and critical.marker.color == charts.CRITICAL_COLOUR
    for f in range(3):
        trace = next(t for t in fig.data if t.name == f"frame {f}")
        assert {c[1] for c in trace.customdata} == {f} and trace.marker.color == charts.FRAME_COLOURS[f]
    assert sum(len(t.x) for t in fig.data if t.type == "bar") == 24


def test_many_frames_share_one_trace_with_a_colour_scale():
    assignments = [Assignment("a", "cpu0", 2 * f, 2 * f + 1, f) for f in range(charts.MAX_FRAME_TRACES + 4)]
    fig = charts.gantt_figure(EngineSchedule("manual", assignments), critical=[])
    (trace,) = [t for t in fig.data if t.type == "bar"]
    assert trace.name == "frames" and list(trace.marker.color) == list(range(charts.MAX_FRAME_TRACES + 4))
    assert trace.marker.showscale and trace.marker.colorbar.title.text == "frame"


def test_comparison_bars_show_each_figure_per_algorithm(fig31_dag):
    out = compare(fig31_dag, board(1), ["heft", "xeft"])
    fig = scheduling_charts.comparison_bars_figure(out["results"], ["heft", "xeft"])
    bars = {t.name: t for t in fig.data}
    assert list(bars["makespan"].x) == ["HEFT", "XEFT"] and list(bars["makespan"].y) == [25, 17]
    assert list(bars["speedup vs VisionWorks (%)"].y) == pytest.approx([100 * 4 / 29, 100 * 12 / 29])
    assert "mean frame latency" not in bars  # one frame: no latency or throughput panels
    with_frames = compare(fig31_dag, board(1), ["heft", "xeft"], frames=2)
    names = {t.name for t in scheduling_charts.comparison_bars_figure(with_frames["results"]).data}
    assert {"mean frame latency", "throughput (frames per time unit)"} <= names


def test_uma_zone_figure_draws_the_boards_zones_and_the_usage():
    fig = device_charts.uma_zone_figure(100.0, 16.2, 57.1, cpu_usage=6.1, gpu_usage=7.0)
    bands = {t.text[0]: (t.base[0], t.base[0] + t.x[0]) for t in fig.data if t.type == "bar"}
    assert bands["zone 1: ZC = SC"] == (0, 16.2) and bands["zone 2: gap < 200 %"] == pytest.approx((16.2, 57.1))
    assert bands["CPU not cache-dependent"] == (0, 100) and "CPU cache-dependent" not in bands
    marks = {t.name: t.x[0] for t in fig.data if t.type == "scatter"}
    assert marks == {"GPU usage": 7.0, "CPU usage": 6.1}
    tx2 = device_charts.uma_zone_figure(15.6, 2.7, None)
    assert {t.text[0] for t in tx2.data if t.type == "bar"} == {
        "zone 1: ZC = SC",
        "zone 3: cache-dependent",
        "CPU not cache-dependent",
        "CPU cache-dependent",
    }
