"""A product that explains itself: the home page's paths and clusters' health, forms with sensible defaults
and their errors at the top, actions shown disabled with their reason, and units on the numbers."""

import re

import pytest
from django.urls import reverse

from apps.jobs.models import Job
from apps.scheduling.models import Schedule
from continuum.engine.core.platform import Platform
from tests.conftest import make_application

pytestmark = pytest.mark.django_db


# ---- home --------------------------------------------------------------------------------------------
def test_home_says_what_it_does_and_disables_steps_without_prerequisites(member):
    body = member.get(reverse("dashboard:home")).content.decode()
    for path in ("Schedule a DAG on boards or a cluster", "Place a ROS graph", "Real-time and verification"):
        assert path in body
    assert "HEFT4K" in body and "RT-Kube" in body and "STL" in body
    # No application and no cluster yet: those steps are disabled, saying why and linking to the fix.
    assert "no application yet" in body and f'href="{reverse("workloads:applications")}#upload"' in body
    assert "no cluster yet" in body and f'href="{reverse("clusters:clusters")}#import"' in body
    assert "no cluster has a Kubernetes API" in body  # pushing needs a live cluster
    assert body.count("disabled") >= 3


def test_home_leads_to_the_latest_application_and_shows_cluster_health(member, fleet, cluster):
    app = make_application(fleet)
    cluster.nodes.filter(pk=cluster.nodes.order_by("pk").first().pk).update(status="NotReady")
    body = member.get(reverse("dashboard:home")).content.decode()
    assert f'href="{reverse("workloads:application", args=[app.pk])}#schedule"' in body
    assert "no application yet" not in body and "no cluster yet" not in body
    ready, total = cluster.nodes.filter(status="Ready").count(), cluster.nodes.count()
    assert f"{ready} / {total} nodes Ready" in body
    assert '<span class="badge node-NotReady">1</span>' in body


def test_api_nav_item_goes_to_the_api_docs(member):
    body = member.get(reverse("dashboard:home")).content.decode()
    assert f'href="{reverse("api-docs")}"' in body and 'href="/api/v1/"' not in body
    docs = member.get(reverse("api-docs"))
    assert docs.status_code == 200 and b"swagger" in docs.content.lower()


# ---- forms: defaults and errors at the top ------------------------------------------------------------
def test_schedule_form_preselects_the_only_cluster_and_heft(member, fleet, cluster):
    app = make_application(fleet, "montage-chameleon-2mass-005d-001.json")
    body = member.get(reverse("workloads:application", args=[app.pk])).content.decode()
    assert f'<option value="{cluster.pk}" selected>' in body
    assert re.search(r'<input type="radio" name="target" value="cluster"[^>]*checked', body)
    assert '<option value="heft" selected>HEFT</option>' in body


def test_errors_are_summarised_at_the_top_of_the_form_with_links(member, fleet):
    app = make_application(fleet, "montage-chameleon-2mass-005d-001.json")
    response = member.post(
        reverse("scheduling:application-schedule", args=[app.pk]),
        {"algorithm": "heft", "target": "platform", "cpus": -1, "gpus": 0, "params": "{oops"},
    )
    body = response.content.decode()
    assert response.status_code == 400
    summary = body[body.index("data-error-summary") : body.index("</div>", body.index("data-error-summary"))]
    assert 'href="#id_cpus"' in summary and "greater than or equal to 0" in summary
    assert 'href="#id_params"' in summary and "not JSON" in summary
    # ...before the form's fields, and by the field as well.
    assert body.index("data-error-summary") < body.index('name="params"')
    assert body.count("greater than or equal to 0") == 2


# ---- topcuoglu-2002 from the dashboard ------------------------------------------------------------------
def test_topcuoglu_named_processors_are_offered_and_scheduled_by_default(member, fleet, cluster):
    app = make_application(fleet)  # topcuoglu-2002: costs per processor p0, p1, p2
    named = Platform.named_by(t.cost for t in app.graph.tasks.values())
    assert [p.id for p in named.processors] == ["p0", "p1", "p2"]
    body = member.get(reverse("workloads:application", args=[app.pk])).content.decode()
    assert "the processors its costs name (p0, p1, p2)" in body
    # The page's defaults, as the browser would send them, schedule it (the paper's makespan: 80).
    response = member.post(
        reverse("scheduling:application-schedule", args=[app.pk]),
        {"algorithm": "heft", "target": "named", "cluster": cluster.pk, "cpus": 4, "gpus": 0},
    )
    assert response.status_code == 302, response.content.decode()[:2000]
    job = Job.objects.get(kind="schedule")
    assert job.state == "succeeded", job.error
    assert Schedule.objects.get(job=job).makespan == 80.0
    compare = member.post(
        reverse("scheduling:application-compare", args=[app.pk]),
        {"compare-algorithms": ["heft", "xeft"], "compare-rank_mode": "mean", "compare-target": "named"},
    )
    assert compare.status_code == 302, compare.content.decode()[:2000]
    assert Job.objects.get(kind="compare").state == "succeeded"


def test_class_cost_dag_has_no_named_target(member, fleet):
    app = make_application(fleet, "montage-chameleon-2mass-005d-001.json")
    assert Platform.named_by(t.cost for t in app.graph.tasks.values()) is None
    body = member.get(reverse("workloads:application", args=[app.pk])).content.decode()
    assert "the processors its costs name" not in body


# ---- disabled actions ---------------------------------------------------------------------------------
def test_push_is_shown_disabled_with_its_reason_and_fix(member, schedule, cluster):
    body = member.get(reverse("scheduling:schedule", args=[schedule.pk])).content.decode()
    assert "Push to Kubernetes</button>" in body and "disabled" in body
    assert "scheduled on a model platform, not a cluster" in body
    Schedule.objects.filter(pk=schedule.pk).update(cluster=cluster)
    body = member.get(reverse("scheduling:schedule", args=[schedule.pk])).content.decode()
    assert f"cluster {cluster.name} has no Kubernetes API configured" in body
    fix = reverse("clusters:cluster", args=[cluster.pk]) + "#kubernetes"
    assert f'href="{fix}"' in body
    assert 'id="kubernetes"' in member.get(fix.split("#")[0]).content.decode()


def test_makespan_has_its_unit(member, schedule):
    body = member.get(reverse("scheduling:schedule", args=[schedule.pk])).content.decode()
    assert '<dd class="big">80 ms</dd>' in body


# ---- re-upload of the same file ------------------------------------------------------------------------
def _upload(client, content: bytes, **fields):
    from django.core.files.uploadedfile import SimpleUploadedFile

    data = {"file": SimpleUploadedFile("topcuoglu.dag.json", content, content_type="application/json"), **fields}
    return client.post(reverse("workloads:applications"), data)


def test_dashboard_reupload_is_refused_with_a_link_unless_asked(member, fleet):
    from apps.workloads.models import Application
    from tests.conftest import DATA

    content = (DATA / "topcuoglu.dag.json").read_bytes()
    assert _upload(member, content).status_code == 302
    first = Application.objects.get()
    again = _upload(member, content)
    body = again.content.decode()
    assert again.status_code == 400 and "this file was uploaded already" in body
    assert f'href="{reverse("workloads:application", args=[first.pk])}"' in body
    assert Application.objects.count() == 1
    assert _upload(member, content, duplicate="on", name="topcuoglu-copy").status_code == 302
    assert sorted(Application.objects.values_list("name", flat=True)) == ["topcuoglu-2002", "topcuoglu-copy"]


def test_api_reupload_answers_400_on_file_unless_duplicate_allow(api, other_api):
    from tests.conftest import DATA

    content = (DATA / "topcuoglu.dag.json").read_bytes()

    def post(client, query="", **fields):
        from django.core.files.uploadedfile import SimpleUploadedFile

        upload = SimpleUploadedFile("t.json", content, content_type="application/json")
        return client.post("/api/v1/applications/import/" + query, {"file": upload, **fields}, format="multipart")

    first = post(api)
    assert first.status_code == 201, first.data
    refused = post(api)
    assert refused.status_code == 400 and f"(id {first.data['id']}," in refused.data["file"][0]
    # Another fleet holding the same bytes is no duplicate of ours (and is not told about ours).
    assert post(other_api).status_code == 201
    assert post(api, "?duplicate=allow").status_code == 201
    assert post(api, duplicate="allow", name="second").status_code == 201
    assert post(api, duplicate="maybe").status_code == 400


# ---- units and the normalise toggle on comparisons ---------------------------------------------------------
def _compare(fleet, user, algorithms, platform, **extra):
    from apps.jobs.services import start_job
    from apps.scheduling.kinds import SchedulingJob
    from apps.scheduling.models import Comparison

    app = make_application(fleet, "montage-chameleon-2mass-005d-001.json")
    args = {"application": app.pk, "algorithms": algorithms, "platform": platform, **extra}
    job = start_job(SchedulingJob.COMPARE, fleet, args, user)
    assert job.state == "succeeded", job.error
    return Comparison.objects.get(job=job)


CPU_GPU = {
    "format": "continuum.platform/v1",
    "processors": [{"id": "cpu0"}, {"id": "cpu1"}, {"id": "gpu0", "class": "gpu"}],
}


def test_comparison_figures_have_units_and_no_exponents(member, fleet, operator):
    from apps.scheduling import charts as scheduling_charts

    comparison = _compare(fleet, operator, ["heft", "xeft"], CPU_GPU, frames=3)
    body = member.get(reverse("scheduling:comparison", args=[comparison.pk])).content.decode()
    assert "Makespan (ms)" in body and "Throughput (frames/s)" in body and "frames per" not in body
    results = comparison.result["results"]
    fig = scheduling_charts.comparison_bars_figure(results, ["heft", "xeft"], "ms")
    bars = {t.name: t for t in fig.data}
    assert "makespan (ms)" in bars and "throughput (frames/s)" in bars
    assert list(bars["throughput (frames/s)"].y) == pytest.approx(
        [results[a]["throughput"] * 1000 for a in ("heft", "xeft")]
    )
    assert all("e+" not in text for t in fig.data for text in t.text)
    assert scheduling_charts.short_number(55890.0) == "55,890" and scheduling_charts.short_number(0.01234) == "0.01234"


def test_normalise_toggle_divides_by_heft(member, fleet, operator):
    from apps.scheduling import charts as scheduling_charts

    comparison = _compare(fleet, operator, ["heft", "gfl"], CPU_GPU)
    url = reverse("scheduling:comparison", args=[comparison.pk])
    plain, normalised = member.get(url).content.decode(), member.get(url + "?normalise=1").content.decode()
    assert 'href="?normalise=1#figures"' in plain and "Figures relative to HEFT" in normalised
    results = comparison.result["results"]
    fig = scheduling_charts.comparison_bars_figure(results, ["heft", "gfl"], "ms", normalise=True)
    makespan = next(t for t in fig.data if t.name.startswith("makespan"))
    assert makespan.name == "makespan (x HEFT)"
    assert list(makespan.y) == pytest.approx([1.0, results["gfl"]["makespan"] / results["heft"]["makespan"]])
    # Without HEFT, the best algorithm is the reference.
    assert (
        scheduling_charts.normalisation_reference({"a": {"makespan": 5.0}, "b": {"makespan": 3.0}}, ["a", "b"]) == "b"
    )


def test_xeft_on_a_cpu_only_dag_says_it_equals_heft(member, fleet, operator):
    comparison = _compare(fleet, operator, ["heft", "xeft"], CPU_GPU)  # Montage: CPU costs only
    results = comparison.result["results"]
    assert results["xeft"]["makespan"] == results["heft"]["makespan"]
    body = member.get(reverse("scheduling:comparison", args=[comparison.pk])).content.decode()
    assert "XEFT equals HEFT here: the DAG has no GPU-only task" in body
    # ...and its Gantt chart keeps the GPU's row, idle as it is.
    from apps.scheduling import charts as scheduling_charts
    from continuum.engine.core.platform import Platform as EnginePlatform

    engine = [(s.algorithm, s.to_engine()) for s in comparison.ordered_schedules()]
    fig = scheduling_charts.comparison_figure(engine, platform=EnginePlatform.from_dict(CPU_GPU))
    rows = [t for t in fig.data if t.name == "rows"]
    assert len(rows) == len(engine) and all("gpu0" in t.y for t in rows)
    assert not any(a.processor == "gpu0" for _, e in engine for a in e.assignments)


def test_schedule_throughput_in_frames_per_second_only(member, fleet, operator):
    from apps.scheduling.views import schedule_metrics

    rows = schedule_metrics({"frames": 4, "throughput": 0.015, "throughput_per_s": 15.0, "mean_latency": 3}, "ms")
    assert [(label, value, unit) for label, value, unit in rows if label == "Throughput"] == [
        ("Throughput", 15.0, " frames/s")
    ]
    rows = schedule_metrics({"frames": 4, "throughput": 0.5}, "steps")
    assert ("Throughput", 0.5, " frames per steps") in rows


def test_preselect_only_chooses_the_only_choice_else_the_fallback(fleet, cluster):
    from django import forms

    from apps.clusters.models import Cluster
    from apps.ui.forms import preselect_only

    field = forms.ModelChoiceField(queryset=Cluster.objects.filter(fleet=fleet))
    preselect_only(field)
    assert field.initial == cluster.pk
    other = Cluster.objects.create(fleet=fleet, name="second")
    field = forms.ModelChoiceField(queryset=Cluster.objects.filter(fleet=fleet))
    preselect_only(field)
    assert field.initial is None
    preselect_only(field, fallback=other)
    assert field.initial == other.pk


def test_same_bytes_read_another_way_are_another_application(api):
    from django.core.files.uploadedfile import SimpleUploadedFile

    from tests.conftest import DATA

    stg = next(DATA.glob("*.stg")).read_bytes()

    def post(**fields):
        upload = SimpleUploadedFile("g.stg", stg, content_type="text/plain")
        return api.post("/api/v1/applications/import/", {"file": upload, **fields}, format="multipart")

    assert post().status_code == 201
    assert post(options='{"ccr": 1, "processors": 2}').status_code == 201  # another DAG from the same file
    assert post(options='{"ccr": 1, "processors": 2}').status_code == 400


def test_placement_push_is_shown_disabled_with_its_reason(member, fleet, cluster):
    from tests.conftest import DATA
    from tests.containers.test_pages import cluster_it, make_graph, place_it

    graph = make_graph(fleet, (DATA / "autoware_reference_system.json").read_bytes())
    placement = place_it(cluster_it(graph), cluster)
    body = member.get(reverse("containers:placement", args=[placement.pk])).content.decode()
    assert "Push to Kubernetes</button>" in body and "its cluster has no Kubernetes API configured" in body
    assert f'href="{reverse("clusters:cluster", args=[cluster.pk])}#kubernetes"' in body


def test_an_unknown_node_counts_as_not_ready_in_red(member, fleet, cluster):
    # A node whose kubelet stopped posting is Unknown (the node lifecycle controller's word): not ready, the alarm.
    cluster.nodes.filter(pk=cluster.nodes.order_by("pk").first().pk).update(status="Unknown")
    body = member.get(reverse("dashboard:home")).content.decode()
    assert '<span class="badge node-NotReady">1</span>' in body
