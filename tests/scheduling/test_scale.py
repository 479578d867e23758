"""Schedules at scale (issues 13 and 15): the bulk store, the bounded API detail and its paginated, filterable
assignments endpoint, the schedule page's paginated and filtered table with a bounded number of queries, the
WebGL Gantt past a few thousand bars, and list pages that read no large column."""

import json

import pytest
from django.db import IntegrityError, transaction
from django.urls import reverse

from apps.scheduling.models import Assignment, Comparison, Schedule
from apps.scheduling.serializers import MAX_INLINE_ASSIGNMENTS
from apps.ui import charts
from apps.workloads.models import Application
from continuum.engine.core.schedule import Assignment as EngineAssignment
from continuum.engine.core.schedule import Schedule as EngineSchedule
from continuum.engine.device import algorithms
from continuum.engine.device.generators import layered_dag, related_platform

pytestmark = pytest.mark.django_db

PLATFORM = related_platform(4, seed=1)


def stored(fleet, tasks: int, frames: int = 1) -> Schedule:
    """A HEFT schedule of a layered DAG of ``tasks`` tasks for ``frames`` frames on four processors, stored."""
    dag = layered_dag(tasks, seed=5, processors=4)
    app = Application(fleet=fleet, name=f"layered-{tasks}")
    app.set_graph(dag)
    app.save()
    result = algorithms.run("heft", dag, PLATFORM, **({"frames": frames} if frames > 1 else {}))
    with transaction.atomic():
        return Schedule.store(result, application=app, platform=PLATFORM)


# ---- storing ----------------------------------------------------------------------------------------------
def test_a_stored_schedule_reads_back_every_field_of_every_assignment(application):
    rows = [
        EngineAssignment(f"t{i}", f"p{i % 3}", float(i), i + 0.5, frame=i % 2, niceness=i % 5 - 2, core=i % 2)
        for i in range(3000)
    ]
    rows.append(EngineAssignment("tab\tand\nnewline\\ \u00e9", "p0", 9000.0, 9001.0))  # COPY's special characters
    engine = EngineSchedule("heft", rows, ranks={"t0": 1.0}, metrics={"frames": 2})
    row = Schedule.store(engine, application=application, platform=PLATFORM)
    back = Schedule.objects.get(pk=row.pk).to_engine()
    assert back.assignments == sorted(rows, key=lambda a: (a.start, a.processor, a.task))
    assert set(Assignment.objects.filter(schedule=row).values_list("placement", flat=True)) == {"not_pushed"}


def test_a_duplicate_assignment_stores_nothing(application):
    rows = [EngineAssignment("a", "p0", 0.0, 1.0), EngineAssignment("a", "p1", 1.0, 2.0)]
    before = Schedule.objects.count()
    with pytest.raises(IntegrityError), transaction.atomic():
        Schedule.store(EngineSchedule("heft", rows), application=application, platform=PLATFORM)
    assert Schedule.objects.count() == before and not Assignment.objects.filter(task="a").exists()


def test_the_job_stores_a_pipelined_schedule_and_reports_done(api, fleet):
    dag = layered_dag(300, seed=2, processors=4)
    app = Application(fleet=fleet, name="layered-300")
    app.set_graph(dag)
    app.save()
    response = api.post(
        f"/api/v1/applications/{app.pk}/schedule/",
        {"algorithm": "heft", "platform": PLATFORM.to_dict(), "frames": 4},
        format="json",
    )
    assert response.status_code == 202, response.data
    job = api.get(f"/api/v1/jobs/{response.data['id']}/").data
    assert job["state"] == "succeeded" and job["progress"] == 100, job
    schedule = Schedule.objects.get(pk=job["result"]["schedule"])
    assert schedule.assignments.count() == 1200


# ---- the API -------------------------------------------------------------------------------------------------
def test_the_schedule_detail_is_bounded_and_links_its_assignments(api, fleet, django_assert_max_num_queries):
    schedule = stored(fleet, 400, frames=3)  # 1200 assignments
    with django_assert_max_num_queries(12):
        data = api.get(f"/api/v1/schedules/{schedule.pk}/").data
    assert len(data["assignments"]) == MAX_INLINE_ASSIGNMENTS
    assert data["assignment_count"] == 1200 and data["assignments_complete"] is False
    first = list(schedule.assignments.values_list("task", "frame")[:MAX_INLINE_ASSIGNMENTS])
    assert [(a["task"], a["frame"]) for a in data["assignments"]] == first
    assert data["assignments_url"].endswith(f"/api/v1/schedules/{schedule.pk}/assignments/")


def test_a_small_schedule_detail_keeps_every_assignment_inline(api, schedule):
    data = api.get(f"/api/v1/schedules/{schedule.pk}/").data
    assert len(data["assignments"]) == data["assignment_count"] == 10 and data["assignments_complete"] is True


def test_the_assignments_endpoint_pages_and_filters(api, fleet, django_assert_max_num_queries):
    schedule = stored(fleet, 200, frames=3)
    url = f"/api/v1/schedules/{schedule.pk}/assignments/"
    with django_assert_max_num_queries(12):
        page = api.get(url, {"limit": 50, "offset": 100}).data
    everything = list(schedule.assignments.values_list("task", "frame"))
    assert page["count"] == 600 and [(a["task"], a["frame"]) for a in page["results"]] == everything[100:150]

    on_p1 = api.get(url, {"processor": "p1", "frame": 2, "limit": 500}).data
    expected = schedule.assignments.filter(processor="p1", frame=2)
    assert on_p1["count"] == expected.count() > 0
    assert {(a["processor"], a["frame"]) for a in on_p1["results"]} == {("p1", 2)}

    tasks = api.get(url, {"task": "19", "limit": 500}).data
    assert tasks["count"] == sum(1 for t, _ in everything if "19" in t) > 0
    assert all("19" in a["task"] for a in tasks["results"])


@pytest.mark.parametrize(
    "query,field",
    [
        ({"frame": "x"}, "frame"),
        ({"frame": "-1"}, "frame"),
        ({"processor": "nowhere"}, "processor"),
        ({"placement": "lost"}, "placement"),
        ({"task": "t" * 201}, "task"),
        ({"limit": "100000"}, "limit"),
        ({"offset": "-3"}, "offset"),
    ],
)
def test_a_bad_assignment_filter_is_a_400_naming_it(api, schedule, query, field):
    response = api.get(f"/api/v1/schedules/{schedule.pk}/assignments/", query)
    assert response.status_code == 400 and field in response.data, response.data


def test_another_fleets_assignments_answer_404(api, foreign):
    assert api.get(f"/api/v1/schedules/{foreign['schedule'].pk}/assignments/").status_code == 404


# ---- the schedule page ---------------------------------------------------------------------------------------
def test_the_schedule_page_shows_one_page_of_rows_with_a_bounded_number_of_queries(
    member, fleet, django_assert_max_num_queries
):
    small = stored(fleet, 60)
    large = stored(fleet, 700, frames=3)  # 2100 bars: past WEBGL_BARS
    for schedule in (small, large):
        with django_assert_max_num_queries(20):
            response = member.get(reverse("scheduling:schedule", args=[schedule.pk]))
        assert response.status_code == 200
    page = response.context["page"]
    assert page.paginator.count == 2100 and len(page.object_list) == 100
    assert response.context["task_count"] == 2100
    html = response.content.decode()
    assert html.count("<tr") < 150  # one page of the table, the per-processor table and the headers
    busy = {p: (n, t) for p, n, t in response.context["per_processor"]}
    for p in ("p0", "p1", "p2", "p3"):
        rows = large.assignments.filter(processor=p)
        assert busy[p][0] == rows.count()
        assert busy[p][1] == pytest.approx(sum(a.finish - a.start for a in rows))


def test_the_schedule_page_filters_and_pages_its_table(member, fleet):
    schedule = stored(fleet, 600, frames=2)
    url = reverse("scheduling:schedule", args=[schedule.pk])
    response = member.get(url, {"processor": "p2", "frame": 1, "page": 2})
    expected = list(schedule.assignments.filter(processor="p2", frame=1).values_list("task", flat=True))
    assert len(expected) > 100, "the filter should leave more than one page"
    page = response.context["page"]
    assert page.number == 2 and page.paginator.count == len(expected)
    assert [a.task for a in page] == expected[100:200]
    html = response.content.decode()
    # Page links keep the filter.
    assert "processor=p2&amp;frame=1&amp;page=1" in html
    task = expected[0]
    found = member.get(url, {"task": task}).context["page"]
    assert found.paginator.count == schedule.assignments.filter(task__icontains=task).count() >= 1


def test_a_bad_filter_on_the_schedule_page_is_a_400_that_says_why(member, fleet):
    schedule = stored(fleet, 30)
    response = member.get(reverse("scheduling:schedule", args=[schedule.pk]), {"processor": "gpu9", "frame": "x"})
    assert response.status_code == 400
    html = response.content.decode()
    assert "no processor &#x27;gpu9&#x27; in this schedule" in html and "A valid integer is required" in html


# ---- the Gantt chart -----------------------------------------------------------------------------------------
def test_past_webgl_bars_the_gantt_is_webgl_lines_carrying_each_bars_facts(fleet):
    schedule = stored(fleet, 250, frames=10)  # 2500 bars, 10 frames
    engine = schedule.to_engine()
    dag = schedule.application.graph
    fig = charts.gantt_figure(engine, platform=PLATFORM, dag=dag)
    traces = [t for t in fig.data if t.type == "scattergl"]
    assert traces and all(t.type == "scattergl" for t in fig.data)
    assert len(traces) <= charts.MAX_FRAME_TRACES + 1  # frames binned, plus the critical path
    durations = {(a.task, a.frame): a.finish - a.start for a in engine.assignments}
    bars = {}
    for t in traces:
        facts = json.loads(t.meta["gantt"])
        assert facts["unit"] == f" {dag.time_unit}"
        for k in range(len(facts["task"])):
            key = (facts["task"][k], facts["frame"][k])
            bars[key] = (facts["processors"][facts["processor"][k]], facts["start"][k], facts["finish"][k])
            assert facts["duration"][k] == float(charts.fmt(durations[key]))
    assert len(bars) == 2500
    for a in engine.assignments:
        assert bars[(a.task, a.frame)] == (a.processor, float(charts.fmt(a.start)), float(charts.fmt(a.finish)))
    critical = next(t for t in traces if t.name == "critical path")
    assert len(json.loads(critical.meta["gantt"])["task"]) == len(engine.critical_path(dag, PLATFORM))
    assert "data-gl-gantt" in charts.to_html(fig)  # static/js/charts.js expands the facts in the browser


def test_below_webgl_bars_the_gantt_keeps_svg_bars_without_bleaching_outlines(fleet):
    schedule = stored(fleet, 400)
    fig = charts.gantt_figure(schedule.to_engine(), platform=PLATFORM, dag=schedule.application.graph)
    bars = [t for t in fig.data if t.type == "bar"]
    assert bars and not [t for t in fig.data if t.type == "scattergl"]
    big = max(bars, key=lambda t: len(t.x))
    assert len(big.x) > charts.OUTLINED_BARS and big.marker.line.width == 0
    # Hover says the duration, not the finish (the base/x pitfall).
    for text, base, width in zip(big.hovertext, big.base, big.x, strict=True):
        assert f"duration: {charts.fmt(width)}" in text and f"start: {charts.fmt(base)}" in text


# ---- list pages ----------------------------------------------------------------------------------------------
def test_the_applications_and_comparisons_lists_read_no_large_column(member, fleet, django_assert_max_num_queries):
    schedule = stored(fleet, 50)
    for i in range(3):
        Comparison.objects.create(
            fleet=fleet,
            application=schedule.application,
            platform=PLATFORM.to_dict(),
            algorithms=["heft"],
            params={"frames": 2},
            result={"padding": "x" * 5000, "i": i},
            best="heft",
        )
    for name in ("workloads:applications", "scheduling:comparisons", "jobs:jobs"):
        with django_assert_max_num_queries(10) as ctx:
            response = member.get(reverse(name))
        assert response.status_code == 200
        for q in ctx.captured_queries:
            sql = q["sql"]
            for column in (
                '"workloads_application"."dag"',
                '"scheduling_comparison"."result"',
                '"jobs_job"."arguments"',
            ):
                assert column not in sql, (name, sql)
    comparisons = member.get(reverse("scheduling:comparisons")).content.decode()
    assert "4 processors" in comparisons
    applications = member.get(reverse("workloads:applications")).context["page"]
    assert {a.name: a.schedule_count for a in applications}[schedule.application.name] == 1
