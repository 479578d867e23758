"""HEFT4K in the dashboard: the schedule panel, the "fail this node" what-if, remap pages and history, and
the chart functions they use."""

import itertools
import re

import pytest
from django.urls import reverse
from django.utils.html import escape

from apps.heft4k.models import RemapEvent
from apps.jobs.models import Job
from apps.jobs.views import job_result_link
from apps.ui import charts
from continuum.engine.core.cluster import cluster_platform
from continuum.engine.core.dag import TaskGraph
from continuum.engine.heft4k.heft4k import heft4k
from continuum.engine.heft4k.k8s_baselines import run_heft4k, run_heft_k8s
from tests.conftest import CLUSTER_DOC

from .fan import FAN_DAG, heft4k_schedule

pytestmark = pytest.mark.django_db


def whatif(member, schedule, node="node1", **extra):
    return member.post(reverse("heft4k:whatif", args=[schedule.pk]), {"node": node, **extra})


def test_heft4k_schedule_page_shows_niceness_and_predicted_vs_simulated(member, fan):
    body = member.get(reverse("scheduling:schedule", args=[fan.pk])).content.decode()
    # Niceness per task in the table.
    assert '<th class="num" title="Linux niceness' in body
    for a in fan.assignments.all():
        assert re.search(rf"<td>{a.task}(?:</td>| <span)[\s\S]*?<td class=\"num\">{a.niceness}</td>", body), a.task
    # Predicted and simulated Gantt charts in one figure on a shared time axis, coloured by niceness.
    assert 'id="gantt-chart"' in body
    assert "Predicted (HEFT4K plan, synchronised)" in body and "Simulated on Kubernetes (Linux CFS, niceness)" in body
    assert '"coloraxis"' in body and re.search(r"niceness: -?\d+", body)
    assert "lost to CPU sharing" in body or "ran alone" in body
    # The simulated makespans, computed by the engine's simulator on the same inputs.
    dag, platform, plan = fan.application.graph, fan.engine_platform(), fan.to_engine()
    table = body[body.index('id="simulated-makespans"') :]
    for makespan in (run_heft4k(dag, platform, plan).makespan, run_heft_k8s(dag, platform, plan).makespan):
        assert f'<td class="num">{makespan:g}</td>' in table
    # The what-if form lists the nodes with their task counts.
    assert f'action="/schedules/{fan.pk}/what-if/"' in body
    assert ">node0 (10 tasks)</option>" in body and ">node1 (4 tasks)</option>" in body
    assert "No remap of this schedule yet." in body


def test_plain_heft_schedules_have_no_heft4k_panel(member, api, cluster):
    from apps.scheduling.models import Schedule

    from .fan import run

    app = api.post("/api/v1/applications/", {"name": "fan", "dag": FAN_DAG}, format="json").data
    job = run(api, f"/api/v1/applications/{app['id']}/schedule/", {"algorithm": "heft", "cluster": cluster.pk})
    schedule = Schedule.objects.get(pk=job["result"]["schedule"])
    body = member.get(reverse("scheduling:schedule", args=[schedule.pk])).content.decode()
    assert "what-if" not in body and "Simulated on Kubernetes" not in body and "Linux niceness" not in body


def test_what_if_shows_the_remap_before_anything_is_pushed_and_applies_it(member, fan):
    response = whatif(member, fan)
    event = RemapEvent.objects.get()
    assert response.status_code == 302 and response["Location"] == reverse("heft4k:remap", args=[event.pk])
    assert (event.trigger, event.status, event.decision) == ("what-if", "what-if", "partial")

    body = member.get(response["Location"]).content.decode()
    assert "Partial</span> remap of" in body and "without node1" in body
    assert escape(event.reason) in body
    assert f"{event.makespan_before:g} → {event.makespan_after:g}" in body
    assert "computed, nothing pushed" in body
    assert 'id="remap-chart"' in body and f"Before: schedule #{fan.pk}" in body
    assert f"After: partial remap, schedule #{event.new_schedule_id}" in body
    changes = body[body.index('id="remap-changes"') :]
    for task in event.moved_tasks:
        assert f"<td>{task}</td>" in changes
    assert changes.count("<tr>") == 1 + len(event.moved_tasks)
    assert 'id="apply-remap"' in body and "4 to recreate, 18 kept" in body

    response = member.post(reverse("heft4k:remap-apply", args=[event.pk]), follow=True)
    body = response.content.decode()
    event.refresh_from_db()
    assert event.status == "not-pushed"
    assert "Applied: stored; the cluster has no Kubernetes API, so no pod was changed." in body
    assert 'id="apply-remap"' not in body

    # The schedule pages link both ways, and the application keeps the history.
    new_page = member.get(reverse("scheduling:schedule", args=[event.new_schedule_id])).content.decode()
    assert f'Produced by <a href="/remaps/{event.pk}/">remap #{event.pk}</a>' in new_page
    old_page = member.get(reverse("scheduling:schedule", args=[fan.pk])).content.decode()
    assert f'<a href="/remaps/{event.pk}/">#{event.pk}</a>' in old_page
    app_page = member.get(reverse("workloads:application", args=[fan.application_id])).content.decode()
    history = app_page[app_page.index("Remapping history") :]
    assert f'<a href="/remaps/{event.pk}/">#{event.pk}</a>' in history and "partial" in history
    assert "4 / 4" in history  # lost / moved


def test_bad_what_if_answers_400_in_the_page_and_stores_nothing(member, fan):
    jobs = Job.objects.count()
    response = whatif(member, fan, threshold=150)
    assert response.status_code == 400
    assert "Ensure this value is less than or equal to 100." in response.content.decode()
    response = whatif(member, fan, node="node9")
    assert response.status_code == 400
    assert "Select a valid choice. node9 is not one of the available choices." in response.content.decode()
    assert Job.objects.count() == jobs and RemapEvent.objects.count() == 0


def test_a_total_what_if_lists_the_critical_task(member, fan):
    whatif(member, fan, node="node0")
    event = RemapEvent.objects.get()
    body = member.get(reverse("heft4k:remap", args=[event.pk])).content.decode()
    assert "Total</span> remap" in body and "Critical task lost: sink" in body


def test_remap_list_and_nav(member, fan):
    whatif(member, fan, node="node2")
    whatif(member, fan, node="node3", threshold=5)
    body = member.get(reverse("heft4k:remaps")).content.decode()
    assert 'href="/remaps/" class="active">Remaps</a>' in body
    assert body.count('<a href="/remaps/') == 2 + 1  # two events and the nav entry
    assert ">partial</span>" in body and ">total</span>" in body
    only = member.get(reverse("heft4k:remaps") + f"?application={fan.application_id}").content.decode()
    assert f'Remaps of <a href="/applications/{fan.application_id}/">' in only


def test_remap_pages_need_login_and_stay_in_the_fleet(client, member, fan, other_api, fleets, django_user_model):
    whatif(member, fan)
    event = RemapEvent.objects.get()
    client.logout()
    for url in (reverse("heft4k:remaps"), reverse("heft4k:remap", args=[event.pk])):
        response = client.get(url)
        assert response.status_code == 302 and response["Location"].startswith(reverse("login"))
    for url in (reverse("heft4k:whatif", args=[fan.pk]), reverse("heft4k:remap-apply", args=[event.pk])):
        response = client.post(url, {"node": "node1"})
        assert response.status_code == 302 and response["Location"].startswith(reverse("login"))
    stranger = django_user_model.objects.create_user("beta-operator", password="x" * 12)
    fleets[1].members.add(stranger)
    client.force_login(stranger)
    assert client.get(reverse("heft4k:remap", args=[event.pk])).status_code == 404
    assert client.post(reverse("heft4k:whatif", args=[fan.pk]), {"node": "node1"}).status_code == 404
    assert client.post(reverse("heft4k:remap-apply", args=[event.pk])).status_code == 404
    assert client.get(reverse("heft4k:remaps") + f"?application={fan.application_id}").status_code == 404
    assert f'href="/remaps/{event.pk}/"' not in client.get(reverse("heft4k:remaps")).content.decode()
    assert RemapEvent.objects.get().status == "what-if"


def test_a_remap_job_links_to_its_remap_page(member, fan):
    whatif(member, fan)
    event = RemapEvent.objects.get()
    assert job_result_link(event.job) == reverse("heft4k:remap", args=[event.pk])
    body = member.get(reverse("jobs:job", args=[event.job.pk])).content.decode()
    assert f'href="/remaps/{event.pk}/"' in body


# ---- charts -------------------------------------------------------------------------------------------
def fan_plan():
    dag = TaskGraph.from_dict(FAN_DAG)
    platform = cluster_platform(CLUSTER_DOC)
    return dag, platform, heft4k(dag, platform)


def bars(fig):
    return [t for t in fig.data if t.type == "bar"]


def test_gantt_lanes_give_every_cpu_its_row_and_never_overlap():
    dag, platform, plan = fan_plan()
    rows, row_of = charts.gantt_rows(plan, platform, lanes=True)
    assert rows[:4] == ["node0 · cpu0", "node0 · cpu1", "node0 · cpu2", "node0 · cpu3"] and len(rows) == 16
    assert all(row_of[(a.task, 0)] == f"{a.processor} · cpu{a.core}" for a in plan.assignments)
    simulated = run_heft4k(dag, platform, plan)
    rows, row_of = charts.gantt_rows(simulated, platform, lanes=True)
    lanes: dict[str, list] = {}
    for a in simulated.assignments:
        lanes.setdefault(row_of[(a.task, 0)], []).append((a.start, a.finish))
    for spans in lanes.values():  # first-fit lanes: no two bars of a row overlap
        spans.sort()
        assert all(b[0] >= a[1] - 1e-9 for a, b in itertools.pairwise(spans))
    assert charts.gantt_rows(plan, platform)[0] == ["node0", "node1", "node2", "node3"]


def test_stacked_gantt_shares_the_time_axis_and_colours_by_niceness():
    dag, platform, plan = fan_plan()
    simulated = run_heft4k(dag, platform, plan)
    critical = set(plan.critical_path(dag, platform))
    fig = charts.stacked_gantt_figure(
        [charts.GanttPanel("plan", plan, platform, critical), charts.GanttPanel("run", simulated, platform, critical)],
        "ms",
        colour_by_niceness=True,
    )
    drawn = bars(fig)
    assert sum(len(t.x) for t in drawn) == 2 * len(dag.tasks)
    assert {t.yaxis for t in drawn} == {"y", "y2"} and fig.layout.xaxis.matches == "x2"
    assert fig.layout.xaxis2.title.text == "time (ms)"
    end = max(plan.makespan, simulated.makespan)
    assert fig.layout.xaxis2.range[1] == pytest.approx(end * 1.03)
    nice = {a.task: a.niceness for a in plan.assignments}
    for trace in drawn:
        assert trace.marker.coloraxis == "coloraxis"
        assert list(trace.marker.color) == [nice[c[0]] for c in trace.customdata]
    assert fig.layout.coloraxis.cmin == min(nice.values()) and fig.layout.coloraxis.cmax == max(nice.values())
    assert [t.showlegend for t in drawn] == [True, True, False, False]  # one legend entry per kind
    outlined = [t for t in drawn if t.name == "critical path"]
    assert all(t.marker.line.color == charts.CRITICAL_COLOUR and t.marker.line.width == 3 for t in outlined)
    assert "plan · makespan 27 ms" in [a.text for a in fig.layout.annotations]


def test_gantt_hover_shows_niceness_and_notes_only_when_there_are_some():
    dag, platform, plan = fan_plan()
    trace = bars(charts.gantt_figure(plan, platform, dag, colour_by_niceness=True))[0]
    assert all(c[5] == next(a.niceness for a in plan.assignments if a.task == c[0]) for c in trace.customdata)
    assert all(text.endswith(f"niceness: {c[5]}") for text, c in zip(trace.hovertext, trace.customdata, strict=True))
    from continuum.engine.device.heft import heft

    plain = bars(charts.gantt_figure(heft(dag, platform), platform, dag))[0]
    assert not any("niceness" in text for text in plain.hovertext) and plain.marker.color == charts.TASK_COLOUR


def test_multi_frame_heft4k_page_shows_the_frame_figures_and_the_heft4k_panel(member, api, cluster):
    schedule = heft4k_schedule(api, cluster, frames=2)
    assert schedule.metrics["frames"] == 2
    body = member.get(reverse("scheduling:schedule", args=[schedule.pk])).content.decode()
    # The frame figures (device-level scheduling) ...
    assert 'id="metrics"' in body and "Mean frame latency" in body and "Frame buffers used" in body
    # ... with idle time per CPU of the 4-CPU nodes: never negative, the CPUs shown.
    assert 0 <= schedule.metrics["idle"] < 1 and min(schedule.metrics["idle_per_processor"].values()) >= 0
    idle = body[body.index('id="idle-table"') :]
    assert '<th class="num">CPUs</th>' in idle and '<td>node0</td><td class="num">4</td>' in idle
    # ... and the HEFT4K panel: niceness colours, the what-if section; no simulation of folded frames.
    assert 'id="what-if"' in body and '"coloraxis"' in body and re.search(r"niceness: -?\d+", body)
    assert "Not simulated: the CFS simulation runs one frame and this schedule has 2" in body
    assert 'id="simulated-makespans"' not in body and "Simulated on Kubernetes" not in body
    assert "Remapping needs a single-frame schedule" in body


def test_one_gantt_implementation_for_single_and_stacked_charts():
    """gantt_figure and stacked_gantt_figure (used by comparisons and the HEFT4K pages) draw the same bars."""
    dag, platform, plan = fan_plan()
    critical = set(plan.critical_path(dag, platform))
    for nice in (False, True):
        single = bars(charts.gantt_figure(plan, platform, dag, lanes=True, colour_by_niceness=nice))
        stacked = bars(
            charts.stacked_gantt_figure([charts.GanttPanel("plan", plan, platform, critical)], colour_by_niceness=nice)
        )
        assert [t.name for t in single] == [t.name for t in stacked] == ["task", "critical path"]
        for a, b in zip(single, stacked, strict=True):
            assert (list(a.y), list(a.base), list(a.x), a.marker.color) == (
                list(b.y),
                list(b.base),
                list(b.x),
                b.marker.color,
            )
