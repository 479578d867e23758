"""Dashboard pages: login, fleet scoping, forms that reject bad input, and the chart functions."""

import json

import pytest
from django.contrib.staticfiles import finders
from django.core.files.uploadedfile import SimpleUploadedFile
from django.urls import reverse

from apps.jobs.models import Job
from apps.jobs.registry import HANDLERS
from apps.scheduling.models import Schedule
from apps.ui import charts
from apps.workloads.models import Application
from continuum.engine.core.dag import TaskGraph
from continuum.engine.core.platform import Platform, Processor
from continuum.engine.core.schedule import Assignment
from continuum.engine.core.schedule import Schedule as EngineSchedule
from continuum.engine.device.heft import heft
from tests.conftest import DATA, make_application

pytestmark = pytest.mark.django_db


def page_urls(cluster, application, schedule) -> list[str]:
    return [
        reverse("dashboard:home"),
        reverse("clusters:clusters"),
        reverse("clusters:cluster", args=[cluster.pk]),
        reverse("workloads:applications"),
        reverse("workloads:application", args=[application.pk]),
        reverse("scheduling:schedules"),
        reverse("scheduling:schedule", args=[schedule.pk]),
        reverse("jobs:jobs"),
        reverse("jobs:job", args=[schedule.job.pk]),
    ]


def upload(client, filename: str, content: bytes | str, **fields):
    if isinstance(content, str):
        content = content.encode()
    data = {"file": SimpleUploadedFile(filename, content, content_type="application/json"), **fields}
    return client.post(reverse("workloads:applications"), data)


def dag_doc(tasks, edges, name="bad-dag"):
    return json.dumps({"format": "continuum.dag/v1", "name": name, "tasks": tasks, "edges": edges})


# ---- login ----------------------------------------------------------------------------------------
def test_every_page_requires_login(client, cluster, application, schedule):
    for url in page_urls(cluster, application, schedule):
        response = client.get(url)
        assert response.status_code == 302, url
        assert response["Location"].startswith(reverse("login") + "?next="), url


def test_forms_require_login_and_store_nothing(client, application, schedule):
    apps_before, jobs_before = Application.objects.count(), Job.objects.count()
    posts = [
        (
            reverse("workloads:applications"),
            {"file": SimpleUploadedFile("a.json", (DATA / "topcuoglu.dag.json").read_bytes())},
        ),
        (
            reverse("scheduling:application-schedule", args=[application.pk]),
            {"algorithm": "heft", "target": "platform", "cpus": 2},
        ),
        (reverse("scheduling:schedule-push", args=[schedule.pk]), {}),
    ]
    for url, data in posts:
        response = client.post(url, data)
        assert response.status_code == 302 and response["Location"].startswith(reverse("login")), url
    assert Application.objects.count() == apps_before
    assert Job.objects.count() == jobs_before


def test_login_page_logs_in(client, operator):
    response = client.get(reverse("login"))
    assert response.status_code == 200 and b'name="password"' in response.content
    bad = client.post(reverse("login"), {"username": "operator", "password": "wrong"})
    assert bad.status_code == 200 and b"form-error" in bad.content
    good = client.post(reverse("login"), {"username": "operator", "password": "operator-pass-123"})
    assert good.status_code == 302 and good["Location"] == reverse("dashboard:home")


def test_pages_render_for_a_member(member, cluster, application, schedule):
    for url in page_urls(cluster, application, schedule):
        response = member.get(url)
        assert response.status_code == 200, url
        body = response.content.decode()
        assert "Log out" in body and 'href="/static/css/continuum.css"' in body


# ---- fleet scoping --------------------------------------------------------------------------------
def test_other_fleets_objects_answer_404(member, foreign):
    urls = [
        reverse("clusters:cluster", args=[foreign["cluster"].pk]),
        reverse("workloads:application", args=[foreign["application"].pk]),
        reverse("scheduling:schedule", args=[foreign["schedule"].pk]),
        reverse("jobs:job", args=[foreign["job"].pk]),
    ]
    for url in urls:
        assert member.get(url).status_code == 404, url
    jobs_before = Job.objects.count()
    schedule_url = reverse("scheduling:application-schedule", args=[foreign["application"].pk])
    assert member.post(schedule_url, {"algorithm": "heft", "target": "platform", "cpus": 3}).status_code == 404
    assert member.post(reverse("scheduling:schedule-push", args=[foreign["schedule"].pk])).status_code == 404
    assert Job.objects.count() == jobs_before


def test_lists_show_only_own_fleets(member, foreign, cluster, application, schedule):
    for name in ["dashboard:home", "clusters:clusters", "workloads:applications", "scheduling:schedules", "jobs:jobs"]:
        body = member.get(reverse(name)).content.decode()
        assert "beta-secret" not in body, name
        assert str(foreign["job"].pk)[:8] not in body, name
    assert "edge" in member.get(reverse("clusters:clusters")).content.decode()
    assert application.name in member.get(reverse("workloads:applications")).content.decode()


def test_superuser_sees_every_fleet(client, foreign, django_user_model):
    admin = django_user_model.objects.create_superuser("root", password="root-pass-123")
    client.force_login(admin)
    assert client.get(reverse("clusters:cluster", args=[foreign["cluster"].pk])).status_code == 200
    assert "beta-secret-app" in client.get(reverse("workloads:applications")).content.decode()


def test_cannot_schedule_on_another_fleets_cluster(member, application, foreign):
    url = reverse("scheduling:application-schedule", args=[application.pk])
    response = member.post(url, {"algorithm": "heft", "target": "cluster", "cluster": foreign["cluster"].pk})
    assert response.status_code == 400
    assert "Select a valid choice" in response.content.decode()
    assert not Job.objects.filter(fleet=application.fleet).exists()


# ---- upload -----------------------------------------------------------------------------------------
def test_upload_stores_the_application(member, fleet):
    response = upload(member, "montage.json", (DATA / "montage-chameleon-2mass-005d-001.json").read_bytes())
    app = Application.objects.get()
    assert response.status_code == 302 and response["Location"] == reverse("workloads:application", args=[app.pk])
    assert (app.fleet, app.task_count, app.edge_count, app.source_format) == (fleet, 58, 114, "wfformat")
    page = member.get(response["Location"]).content.decode()
    assert "Imported" in page and "58 tasks" in page and 'id="dag-chart"' in page


def test_upload_with_explicit_format_and_name(member):
    upload(member, "t.json", (DATA / "topcuoglu.dag.json").read_bytes(), format="continuum", name="my dag")
    app = Application.objects.get()
    assert (app.name, app.source_format, app.task_count) == ("my dag", "continuum", 10)


BAD_UPLOADS = [
    (
        "cycle",
        dag_doc(
            [{"id": "a", "cost": {"cpu": 1}}, {"id": "b", "cost": {"cpu": 1}}],
            [{"src": "a", "dst": "b"}, {"src": "b", "dst": "a"}],
        ),
        "the graph has a cycle: a -&gt; b -&gt; a",
    ),
    (
        "dangling",
        dag_doc([{"id": "a", "cost": {"cpu": 1}}], [{"src": "a", "dst": "ghost"}]),
        "edge a-&gt;ghost refers to unknown task &#x27;ghost&#x27;",
    ),
    (
        "negative",
        dag_doc([{"id": "a", "cost": {"cpu": -3}}], []),
        "task &#x27;a&#x27; has an invalid cost -3 on &#x27;cpu&#x27;",
    ),
    ("malformed", '{"format": "continuum.dag/v1",\n "tasks": [\n  {"id": "a",, }]}', "malformed JSON at line 3"),
    ("binary", b"\xff\xfe\x00garbage", "not UTF-8"),
]


@pytest.mark.parametrize(("case", "content", "message"), BAD_UPLOADS, ids=[c[0] for c in BAD_UPLOADS])
def test_bad_upload_shows_the_error_and_stores_nothing(member, case, content, message):
    response = upload(member, f"{case}.json", content)
    assert response.status_code == 400
    body = response.content.decode()
    assert "Nothing was imported" in body
    assert f"{case}.json: " in body
    assert message in body
    assert Application.objects.count() == 0


def test_upload_without_file_or_with_unknown_format(member):
    response = member.post(reverse("workloads:applications"), {})
    assert response.status_code == 400 and "This field is required" in response.content.decode()
    response = upload(member, "t.json", (DATA / "topcuoglu.dag.json").read_bytes(), format="yaml")
    assert response.status_code == 400 and "Select a valid choice" in response.content.decode()
    assert Application.objects.count() == 0


def test_fleet_choice_only_when_several_and_only_visible(member, operator, fleets, django_user_model):
    page = member.get(reverse("workloads:applications")).content.decode()
    assert f'<input type="hidden" name="fleet" value="{fleets[0].pk}"' in page
    # A fleet the user is not in is refused.
    response = upload(member, "t.json", (DATA / "topcuoglu.dag.json").read_bytes(), fleet=fleets[1].pk)
    assert response.status_code == 400 and Application.objects.count() == 0
    fleets[1].members.add(operator)
    page = member.get(reverse("workloads:applications")).content.decode()
    assert '<select name="fleet"' in page and "Beta robots" in page
    upload(member, "t.json", (DATA / "topcuoglu.dag.json").read_bytes(), fleet=fleets[1].pk)
    assert Application.objects.get().fleet == fleets[1]


def test_user_without_fleet_cannot_upload(client, django_user_model):
    loner = django_user_model.objects.create_user("loner", password="loner-pass-123")
    client.force_login(loner)
    page = client.get(reverse("workloads:applications")).content.decode()
    assert "not a member of any fleet" in page and 'type="file"' not in page
    response = upload(client, "t.json", (DATA / "topcuoglu.dag.json").read_bytes())
    assert response.status_code == 400 and Application.objects.count() == 0


# ---- scheduling form --------------------------------------------------------------------------------
def test_schedule_on_a_cluster_runs_the_job_and_links_the_gantt_chart(member, fleet, cluster):
    app = make_application(fleet, "montage-chameleon-2mass-005d-001.json")
    page = member.get(reverse("workloads:application", args=[app.pk])).content.decode()
    assert '<option value="heft" selected>HEFT</option>' in page and f'value="{cluster.pk}"' in page
    response = member.post(
        reverse("scheduling:application-schedule", args=[app.pk]),
        {"algorithm": "heft", "target": "cluster", "cluster": cluster.pk},
    )
    job = Job.objects.get(kind="schedule")
    assert response.status_code == 302 and response["Location"] == reverse("jobs:job", args=[job.pk])
    assert job.state == "succeeded" and job.arguments["cluster"] == cluster.pk
    schedule = Schedule.objects.get(job=job)
    assert schedule.assignments.count() == 58
    assert not schedule.to_engine().violations(app.graph, schedule.engine_platform())
    job_page = member.get(response["Location"]).content.decode()
    assert reverse("scheduling:schedule", args=[schedule.pk]) in job_page
    gantt = member.get(reverse("scheduling:schedule", args=[schedule.pk])).content.decode()
    assert 'id="gantt-chart"' in gantt and "critical path" in gantt.lower()


def test_schedule_on_cpus_and_gpus(member, fleet):
    app = make_application(fleet, "montage-chameleon-2mass-005d-001.json")
    response = member.post(
        reverse("scheduling:application-schedule", args=[app.pk]),
        {"algorithm": "heft", "target": "platform", "cpus": 2, "gpus": 1, "params": '{"rank_mode": "max"}'},
    )
    assert response.status_code == 302
    schedule = Schedule.objects.get()
    assert [p["id"] for p in schedule.platform["processors"]] == ["cpu0", "cpu1", "gpu0"]
    assert schedule.params.get("rank_mode") == "max"
    # Montage only has CPU costs: nothing lands on the GPU.
    assert {a.processor for a in schedule.assignments.all()} <= {"cpu0", "cpu1"}


@pytest.mark.parametrize(
    ("data", "message"),
    [
        ({"target": "platform", "cpus": 0, "gpus": 0}, "need at least one processor"),
        ({"target": "platform", "cpus": -1}, "greater than or equal to 0"),
        ({"target": "platform", "cpus": 2, "params": "{oops"}, "not JSON"),
        ({"target": "platform", "cpus": 2, "params": "[1, 2]"}, "must be a JSON object"),
        ({"target": "cluster"}, "choose a cluster"),
        # The Topcuoglu tasks name processors p0..p2 only: a generic CPU cannot run them.
        ({"target": "platform", "cpus": 3}, "task &#x27;0&#x27; cannot run on any processor"),
        ({"target": "platform", "cpus": 3, "algorithm": "nope"}, "Select a valid choice"),
    ],
)
def test_bad_schedule_requests_are_shown_and_start_no_job(member, application, data, message):
    response = member.post(
        reverse("scheduling:application-schedule", args=[application.pk]), {"algorithm": "heft", **data}
    )
    assert response.status_code == 400
    assert message in response.content.decode()
    assert Job.objects.count() == 0


def test_cluster_without_ready_node_is_refused(member, fleet, cluster):
    cluster.nodes.update(status="NotReady")
    app = make_application(fleet, "montage-chameleon-2mass-005d-001.json")
    response = member.post(
        reverse("scheduling:application-schedule", args=[app.pk]),
        {"algorithm": "heft", "target": "cluster", "cluster": cluster.pk},
    )
    assert response.status_code == 400 and "has no Ready node" in response.content.decode()
    assert Job.objects.count() == 0


# ---- schedule page and push -----------------------------------------------------------------------
def test_schedule_page_draws_the_gantt_chart_from_static_plotly(member, schedule):
    body = member.get(reverse("scheduling:schedule", args=[schedule.pk])).content.decode()
    assert '<script src="/static/vendor/plotly.min.js"></script>' in body
    assert "cdn" not in body.lower()
    assert 'id="gantt-chart"' in body and 'data-figure="gantt-chart-figure"' in body
    assert "makespan 80" in body
    # Every assignment is listed with its placement status.
    assert body.count('<td><span class="badge placement-not_pushed">') == 10
    assert "Push to Kubernetes</button>" in body and "scheduled on a model platform" in body  # disabled, saying why


def test_plotly_js_is_a_static_file():
    path = finders.find("vendor/plotly.min.js")
    assert path, "static/vendor/plotly.min.js is missing"
    with open(path, encoding="utf-8") as f:
        assert "plotly.js v" in f.read(200)


def test_push_button_only_with_a_kubeconfig(member, schedule, cluster):
    url = reverse("scheduling:schedule-push", args=[schedule.pk])
    response = member.post(url, follow=True)
    assert "Nothing to push to: scheduled on a model platform" in response.content.decode()
    assert not Job.objects.filter(kind="push_schedule").exists()
    Schedule.objects.filter(pk=schedule.pk).update(cluster=cluster)
    cluster.kubeconfig = "apiVersion: v1\nkind: Config\n"
    cluster.save()
    body = member.get(reverse("scheduling:schedule", args=[schedule.pk])).content.decode()
    assert "Push to Kubernetes" in body and f'action="{url}"' in body


def test_push_starts_a_push_schedule_job(member, schedule, cluster, monkeypatch):
    cluster.kubeconfig = "apiVersion: v1\nkind: Config\n"
    cluster.save()
    Schedule.objects.filter(pk=schedule.pk).update(cluster=cluster)
    seen = []

    def fake_push(job, progress):
        seen.append(dict(job.arguments))
        return {"schedule": job.arguments["schedule"], "bound": 10}, f"/api/v1/schedules/{job.arguments['schedule']}/"

    monkeypatch.setitem(HANDLERS, "push_schedule", fake_push)
    response = member.post(reverse("scheduling:schedule-push", args=[schedule.pk]))
    job = Job.objects.get(kind="push_schedule")
    assert response["Location"] == reverse("jobs:job", args=[job.pk])
    assert seen == [{"schedule": schedule.pk}] and job.state == "succeeded"
    assert reverse("scheduling:schedule", args=[schedule.pk]) in member.get(response["Location"]).content.decode()


def test_push_without_a_push_handler_says_so(member, schedule, cluster, monkeypatch):
    cluster.kubeconfig = "apiVersion: v1\nkind: Config\n"
    cluster.save()
    Schedule.objects.filter(pk=schedule.pk).update(cluster=cluster)
    monkeypatch.delitem(HANDLERS, "push_schedule", raising=False)
    response = member.post(reverse("scheduling:schedule-push", args=[schedule.pk]), follow=True)
    assert "not available" in response.content.decode()
    assert not Job.objects.filter(kind="push_schedule").exists()


# ---- jobs -------------------------------------------------------------------------------------------
def test_running_job_page_polls_the_api(member, fleet):
    job = Job.objects.create(fleet=fleet, kind="schedule", state="running", progress=42, message="placed 4/10 tasks")
    body = member.get(reverse("jobs:job", args=[job.pk])).content.decode()
    assert f'data-api-url="/api/v1/jobs/{job.pk}/"' in body and 'data-done="false"' in body
    assert 'style="width: 42%"' in body and "placed 4/10 tasks" in body
    assert '<script src="/static/js/job-progress.js"></script>' in body
    # The poller's endpoint answers the operator's session.
    data = member.get(f"/api/v1/jobs/{job.pk}/").json()
    assert (data["state"], data["progress"], data["message"]) == ("running", 42, "placed 4/10 tasks")


def test_failed_job_shows_its_error(member, fleet):
    job = Job.objects.create(
        fleet=fleet, kind="schedule", state="failed", progress=3, error="task 'x' cannot run on any processor"
    )
    body = member.get(reverse("jobs:job", args=[job.pk])).content.decode()
    assert "task &#x27;x&#x27; cannot run on any processor" in body and 'data-done="true"' in body
    assert "Open the result" not in body


def test_job_list_filters_by_state(member, fleet):
    Job.objects.create(fleet=fleet, kind="schedule", state="failed")
    Job.objects.create(fleet=fleet, kind="push_schedule", state="running")
    body = member.get(reverse("jobs:jobs") + "?state=failed").content.decode()
    # Listed by what they do, in words (the kinds' titles).
    assert ">Schedule an application&#x27;s DAG</a>" in body and ">Push a schedule&#x27;s pods" not in body


# ---- chart functions ----------------------------------------------------------------------------------
def topcuoglu():
    dag = TaskGraph.from_dict(json.loads((DATA / "topcuoglu.dag.json").read_text()))
    platform = Platform.from_dict(json.loads((DATA / "topcuoglu.platform.json").read_text()))
    return dag, platform, heft(dag, platform)


def bars(fig):
    return [t for t in fig.data if t.type == "bar"]


def test_gantt_has_one_bar_per_assignment_on_a_numeric_axis():
    dag, platform, sched = topcuoglu()
    fig = charts.gantt_figure(sched, platform=platform, dag=dag)
    assert sum(len(t.x) for t in bars(fig)) == len(sched.assignments) == 10
    assert all(t.orientation == "h" for t in bars(fig))
    assert fig.layout.xaxis.type == "linear"
    assert list(fig.layout.yaxis.categoryarray) == ["p0", "p1", "p2"]
    # base = start and x = duration reproduce every assignment exactly.
    drawn = {
        (c[0], c[1]): (c[2], b, b + x) for t in bars(fig) for c, b, x in zip(t.customdata, t.base, t.x, strict=True)
    }
    assert drawn == {(a.task, a.frame): (a.processor, a.start, a.finish) for a in sched.assignments}
    assert max(b + x for t in bars(fig) for b, x in zip(t.base, t.x, strict=True)) == 80


def test_gantt_highlights_the_critical_path():
    dag, platform, sched = topcuoglu()
    path = sched.critical_path(dag, platform)
    fig = charts.gantt_figure(sched, platform=platform, dag=dag)
    normal, critical = bars(fig)
    assert critical.name == "critical path" and critical.showlegend
    assert critical.marker.color == charts.CRITICAL_COLOUR != normal.marker.color
    assert {(c[0], c[1]) for c in critical.customdata} == set(path)
    assert not {(c[0], c[1]) for c in normal.customdata} & set(path)
    # The path runs from time 0 to the makespan.
    starts = {(c[0], c[1]): c[3] for c in critical.customdata}
    finishes = {(c[0], c[1]): c[4] for c in critical.customdata}
    assert starts[path[0]] == 0 and finishes[path[-1]] == 80


def test_gantt_hover_names_task_start_finish_and_frame():
    dag, platform, sched = topcuoglu()
    trace = bars(charts.gantt_figure(sched, platform=platform, dag=dag))[0]
    # Written in Python (tests/ui/test_gantt_hover.py checks the duration): no template arithmetic.
    for (task, frame, processor, start, finish, *_), text in zip(trace.customdata, trace.hovertext, strict=True):
        assert text.startswith(f"<b>{task}</b> (frame {frame})<br>processor: {processor}<br>")
        assert f"start: {charts.fmt(start)} {dag.time_unit}" in text
        assert f"finish: {charts.fmt(finish)} {dag.time_unit}" in text


def test_gantt_keeps_idle_processors_and_labels_frames():
    platform = Platform([Processor("cpu0"), Processor("cpu1"), Processor("gpu0", "gpu")])
    sched = EngineSchedule(
        "manual",
        [Assignment("a", "cpu0", 0, 2, 0), Assignment("a", "cpu0", 2, 4, 1), Assignment("b", "cpu1", 1, 3, 1)],
    )
    fig = charts.gantt_figure(sched, platform=platform, critical=[("a", 1)])
    assert list(fig.layout.yaxis.categoryarray) == ["cpu0", "cpu1", "gpu0"]
    # Two frames: one trace per frame (what is not on the critical path), then the critical path.
    frame0, frame1, critical = bars(fig)
    assert (frame0.name, frame1.name, critical.name) == ("frame 0", "frame 1", "critical path")
    assert list(critical.text) == ["a [1]"] and list(frame0.text) == ["a [0]"] and list(frame1.text) == ["b [1]"]


def test_gantt_without_critical_path_has_no_highlight_trace():
    _, _, sched = topcuoglu()
    fig = charts.gantt_figure(sched)
    assert [t.name for t in bars(fig)] == ["task"] and len(fig.data[0].x) == 10


def test_dag_figure_layers_by_topological_level():
    dag, _, _ = topcuoglu()
    assert charts.dag_levels(dag) == {
        "0": 0,
        "1": 1,
        "2": 1,
        "3": 1,
        "4": 1,
        "5": 1,
        "6": 2,
        "7": 2,
        "8": 2,
        "9": 3,
    }
    pos = charts.dag_layout(dag)
    assert all(pos[e.src][0] < pos[e.dst][0] for e in dag.edges)
    assert len(set(pos.values())) == len(dag.tasks)  # no two tasks on the same spot
    fig = charts.dag_figure(dag)
    tasks = next(t for t in fig.data if t.name == "tasks")
    assert len(tasks.x) == 10
    edges = next(t for t in fig.data if t.name == "edges")
    assert list(edges.x).count(None) == len(dag.edges) == 15
    hover = dict(zip(tasks.text, tasks.hovertext, strict=True))
    assert "p0: 14 ms" in hover["0"] and "p2: 9 ms" in hover["0"]
    arrows = next(t for t in fig.data if t.name == "edge directions")
    assert sum(1 for size in arrows.marker.size if size) == 15 and not fig.layout.annotations  # arrow heads


def test_dag_figure_scales_to_a_real_workflow():
    from continuum.engine.formats import load_dag

    dag = load_dag((DATA / "montage-chameleon-2mass-005d-001.json").read_bytes())
    fig = charts.dag_figure(dag)
    tasks = next(t for t in fig.data if t.name == "tasks")
    assert len(tasks.x) == 58 and tasks.mode == "markers"
    assert fig.layout.height <= 900


def test_network_figure_colours_nodes_by_status():
    platform = Platform(
        [Processor("n1"), Processor("n2"), Processor("n3", "gpu")],
        links=[],
        bandwidth=None,
    )
    fig = charts.network_figure(platform, status={"n1": "Ready", "n2": "NotReady", "n3": "Ready"})
    nodes = {t.name: list(t.text) for t in fig.data if t.name in ("Ready", "NotReady")}
    assert nodes == {"Ready": ["n1", "n3"], "NotReady": ["n2"]}
    ready = next(t for t in fig.data if t.name == "Ready")
    assert list(ready.marker.symbol) == ["circle", "square"]


def test_network_figure_draws_links_with_their_figures(cluster):
    platform = cluster.to_platform(ready_only=False)
    fig = charts.network_figure(platform, bandwidth_scale=1000, bandwidth_unit="Mbit/s", latency_unit="ms")
    links = next(t for t in fig.data if t.name == "links")
    assert list(links.x).count(None) == 3
    text = next(t for t in fig.data if t.name == "link data").hovertext
    assert "bandwidth: 1000 Mbit/s<br>latency: 0.5 ms" in text[0]


def test_figure_html_leaves_plotly_js_out():
    dag, platform, sched = topcuoglu()
    html = charts.to_html(charts.gantt_figure(sched, platform=platform, dag=dag), div_id="g")
    assert 'id="g"' in html and '<script type="application/json" id="g-figure">' in html
    assert "<script src" not in html and "cdn" not in html.lower()
    assert len(html) < 100_000  # the 4.8 MB library is not inlined


def crossings(dag, pos) -> int:
    """Pairs of drawn edges that cross (edges sharing a task do not count)."""

    def side(a, b, c) -> int:
        v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        return (v > 1e-9) - (v < -1e-9)

    segs = [(pos[e.src], pos[e.dst]) for e in dag.edges]
    count = 0
    for i, (p1, p2) in enumerate(segs):
        for p3, p4 in segs[i + 1 :]:
            if len({p1, p2, p3, p4}) == 4 and side(p1, p2, p3) * side(p1, p2, p4) < 0:
                count += side(p3, p4, p1) * side(p3, p4, p2) < 0
    return count


def test_barycentre_sweeps_remove_crossings():
    dag, _, _ = topcuoglu()
    assert crossings(dag, charts.dag_layout(dag, sweeps=0)) == 5  # tasks in input order
    assert crossings(dag, charts.dag_layout(dag)) == 1


def test_wide_cost_ranges_get_a_log_colour_scale():
    from continuum.engine.formats import load_dag

    montage = load_dag((DATA / "montage-chameleon-2mass-005d-001.json").read_bytes())
    bar = next(t for t in charts.dag_figure(montage).data if t.name == "tasks").marker.colorbar
    assert list(bar.ticktext) == ["10", "100", "1k", "10k", "100k"]
    dag, _, _ = topcuoglu()  # costs 5..21: linear
    assert next(t for t in charts.dag_figure(dag).data if t.name == "tasks").marker.colorbar.ticktext is None


def test_num_filter_trims_zeros_but_keeps_precision():
    from apps.ui.templatetags.ui import num

    assert [num(0.5), num(1000.0), num(54026.0021), num(-0.0001), num(None), num("x")] == [
        "0.5",
        "1000",
        "54026.002",
        "0",
        "—",
        "x",
    ]
