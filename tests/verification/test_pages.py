"""Verification pages of the dashboard: login required, fleet scoping (404), the overview with assertion
status and the monitor-to-node map, a stored simulation drawn as a migration timeline."""

import pytest
from django.urls import reverse

from apps.jobs.services import start_job
from apps.verification.kinds import VerificationJob
from apps.verification.models import AllocationRun, Assertion, Monitor, Violation

pytestmark = pytest.mark.django_db


@pytest.fixture
def monitored(fleet, cluster):
    a = Assertion.objects.create(fleet=fleet, name="arrives", text="G(speed > 0 -> F[0,5000](arrived))")
    node = cluster.nodes.get(name="node1")
    m = Monitor.objects.create(fleet=fleet, assertion=a, cluster=cluster, name="m-arrives", node=node, verdict="fail")
    Violation.objects.create(
        monitor=m, time_ms=16000, instance_start_ms=10000, event=["speed", 0, 16000], handler="in-process"
    )
    Monitor.objects.create(fleet=fleet, assertion=a, cluster=cluster, name="m-spare")
    return a


@pytest.fixture
def simulation(fleet):
    job = start_job(VerificationJob.VERIFICATION_SIMULATION, fleet, {"scenario": "kairos", "duration_s": 25})
    assert job.state == "succeeded", job.error
    return job


@pytest.fixture
def foreign(fleets):
    other = fleets[1]
    a = Assertion.objects.create(fleet=other, name="beta-secret-assertion", text="G(a -> b)")
    run = AllocationRun.objects.create(fleet=other, status="optimal", nodes={"x": {"cpu": 1, "monitors": 1}})
    job = start_job(VerificationJob.VERIFICATION_SIMULATION, other, {"scenario": "synthetic", "duration_s": 5})
    return {"assertion": a, "run": run, "series": job.result["series"]}


def urls(monitored, run_pk, series):
    return [
        reverse("verification:overview"),
        reverse("verification:assertion", args=[monitored.pk]),
        reverse("verification:run", args=[run_pk]),
        reverse("verification:series", args=[series]),
    ]


def test_pages_need_a_login(client, monitored, simulation):
    run = AllocationRun.objects.filter(series__isnull=False).first()
    for url in urls(monitored, run.pk, simulation.result["series"]):
        r = client.get(url)
        assert r.status_code == 302 and r.url.startswith(reverse("login")), url
    r = client.post(reverse("verification:simulate"), {"scenario": "synthetic"})
    assert r.status_code == 302 and r.url.startswith(reverse("login"))


def test_overview_shows_status_violations_and_the_monitor_map(member, monitored, foreign):
    r = member.get(reverse("verification:overview"))
    assert r.status_code == 200
    html = r.content.decode()
    assert "arrives" in html and 'class="badge verdict-fail"' in html
    assert "m-arrives" in html and "m-spare" in html and "not placed" in html  # the map
    assert "16000" in html  # the recent violation
    assert "beta-secret-assertion" not in html
    assert 'href="/verification/"' in html and "Verification</a>" in html  # nav entry


def test_assertion_page_lists_monitors_and_violations(member, monitored):
    r = member.get(reverse("verification:assertion", args=[monitored.pk]))
    html = r.content.decode()
    assert r.status_code == 200 and "G(p0 -&gt; F[0,5000](p1))" in html and "p0 = speed &gt; 0" in html
    assert "node1" in html and "clock tick" not in html and "in-process" in html


def test_other_fleets_pages_answer_404(member, foreign):
    assert member.get(reverse("verification:assertion", args=[foreign["assertion"].pk])).status_code == 404
    assert member.get(reverse("verification:run", args=[foreign["run"].pk])).status_code == 404
    assert member.get(reverse("verification:series", args=[foreign["series"]])).status_code == 404


def test_simulation_page_draws_the_migration_timeline(member, simulation):
    r = member.get(reverse("verification:series", args=[simulation.result["series"]]))
    html = r.content.decode()
    assert r.status_code == 200 and 'id="timeline-chart"' in html
    assert "CPU per node" in html and "Monitors per node" in html and "makespan" in html
    assert "requirement 125 ms" in html
    # the 150 monitors that left the Jetson at t = 20 s, and the first leg's violation
    assert "jetson" in html and "goal not reached" in html
    run = AllocationRun.objects.filter(series=simulation.result["series"], t=20).get()
    assert member.get(reverse("verification:run", args=[run.pk])).url.endswith(simulation.result["series"] + "/")


def test_run_simulation_from_the_page(member, fleet):
    r = member.post(reverse("verification:simulate"), {"scenario": "synthetic", "fleet": fleet.pk})
    assert r.status_code == 302 and "/verification/simulations/" in r.url  # done in-process (no broker)
    assert member.get(r.url).status_code == 200
    r = member.get(reverse("verification:overview"))
    assert "synthetic-4.5.1" in r.content.decode()


def test_allocation_run_page(member, fleet, cluster, monitored):
    job = start_job(VerificationJob.ALLOCATE_MONITORS, fleet, {"cluster": cluster.pk})
    assert job.state == "succeeded", job.error
    r = member.get(job.result["page"])
    html = r.content.decode()
    assert r.status_code == 200 and "Allocation #" in html and "node1" in html and "optimal" in html


def test_admin_rejects_a_malformed_assertion_and_lists_the_models(client, django_user_model, fleet, monitored):
    admin = django_user_model.objects.create_superuser("root", password="root-pass-123")
    client.force_login(admin)
    r = client.post(
        "/admin/verification/assertion/add/",
        {"fleet": fleet.pk, "name": "bad", "text": "G(a -> F(b))", "constants": "{}"},
    )
    assert r.status_code == 200 and "column 9" in r.content.decode()
    assert not Assertion.objects.filter(name="bad").exists()
    for model in ("assertion", "monitor", "handler", "violation", "monitorverdict", "allocationrun", "migrationevent"):
        assert client.get(f"/admin/verification/{model}/").status_code == 200, model
