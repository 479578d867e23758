"""The schedule page reads HEFT4K's simulation from the database: the job that stored the schedule ran the
CFS simulator and the baselines; a schedule stored before that shows a "not computed" note and a button that
starts a job, and no request ever simulates."""

import pytest
from django.urls import reverse

from apps.heft4k import simulation
from apps.heft4k.models import ScheduleSimulation
from apps.jobs.models import Job
from apps.scheduling.models import Schedule
from continuum.engine.heft4k.k8s_baselines import run_heft4k, run_heft_k8s

from .fan import FAN_DAG, heft4k_schedule, run

pytestmark = pytest.mark.django_db


@pytest.fixture
def no_simulator(monkeypatch):
    """Any simulation from here on fails the test."""

    def refuse(*args, **kwargs):
        raise AssertionError("the simulator ran")

    for name in ("run_heft4k", "run_heft_k8s", "run_k8s_default"):
        monkeypatch.setattr(simulation, name, refuse)


def test_the_schedule_job_stores_the_simulation_and_the_baselines(fan):
    stored = ScheduleSimulation.objects.get(schedule=fan)
    dag, platform, plan = fan.application.graph, fan.engine_platform(), fan.to_engine()
    simulated = run_heft4k(dag, platform, plan)
    assert stored.note == ""
    assert stored.simulated["makespan"] == simulated.makespan
    assert len(stored.simulated["assignments"]) == len(dag.tasks)
    assert {(t, f) for t, f, _ in stored.sharing} == {(a.task, a.frame) for a in simulated.assignments}
    names = [row["name"] for row in stored.baselines]
    assert names[0].startswith("HEFT4K") and names[1].startswith("HEFT on Kubernetes") and len(names) == 3
    assert stored.baselines[1]["makespan"] == run_heft_k8s(dag, platform, plan).makespan
    assert stored.baselines[0]["vs_plan"] == pytest.approx(simulated.makespan / plan.makespan - 1.0)


def test_the_page_reads_the_stored_simulation_and_never_simulates(member, fan, no_simulator):
    body = member.get(reverse("scheduling:schedule", args=[fan.pk])).content.decode()
    assert "Simulated on Kubernetes (Linux CFS, niceness)" in body and 'id="simulated-makespans"' in body
    assert "Gantt chart: predicted plan and simulated run" in body
    assert "not computed" not in body and 'id="simulate"' not in body


def test_an_older_schedule_says_not_computed_and_a_job_computes_it(member, fan, no_simulator, monkeypatch):
    ScheduleSimulation.objects.filter(schedule=fan).delete()  # as stored before the jobs simulated
    body = member.get(reverse("scheduling:schedule", args=[fan.pk])).content.decode()
    assert "Simulation not computed" in body and 'id="simulated-makespans"' not in body
    assert f'action="/schedules/{fan.pk}/simulate/"' in body
    assert "Predicted (HEFT4K plan, synchronised)" in body and "Simulated on Kubernetes" not in body
    assert not ScheduleSimulation.objects.filter(schedule=fan).exists()  # the page computed nothing

    monkeypatch.undo()  # the job may simulate
    response = member.post(reverse("heft4k:simulate", args=[fan.pk]))
    job = Job.objects.get(kind="heft4k_simulate")
    assert job.state == Job.State.SUCCEEDED, job.error
    assert job.result == {"schedule": fan.pk, "simulated": True, "note": ""}
    assert response.status_code == 302 and response["Location"] == reverse("scheduling:schedule", args=[fan.pk])
    body = member.get(reverse("scheduling:schedule", args=[fan.pk])).content.decode()
    assert "Simulated on Kubernetes (Linux CFS, niceness)" in body and 'id="simulated-makespans"' in body


def test_simulating_needs_a_login_and_a_post(client, member, fan):
    url = reverse("heft4k:simulate", args=[fan.pk])
    assert member.get(url).status_code == 405
    client.logout()
    assert client.post(url).status_code == 302
    assert not Job.objects.filter(kind="heft4k_simulate").exists()


def test_the_simulate_job_refuses_a_plain_schedule(api, cluster, fleet):
    from apps.jobs.services import start_job

    app = api.post("/api/v1/applications/", {"name": "fan", "dag": FAN_DAG}, format="json").data
    job = run(api, f"/api/v1/applications/{app['id']}/schedule/", {"algorithm": "heft", "cluster": cluster.pk})
    schedule = Schedule.objects.get(pk=job["result"]["schedule"])
    assert not ScheduleSimulation.objects.filter(schedule=schedule).exists()  # only HEFT4K schedules
    failed = start_job("heft4k_simulate", fleet, {"schedule": schedule.pk})
    assert failed.state == Job.State.FAILED and "not a HEFT4K schedule" in failed.error


def test_a_multi_frame_schedule_stores_why_it_is_not_simulated(api, cluster):
    schedule = heft4k_schedule(api, cluster, frames=2)
    stored = ScheduleSimulation.objects.get(schedule=schedule)
    assert stored.note == "not simulated: the CFS simulation runs one frame and this schedule has 2"
    assert stored.simulated == {} and stored.baselines == []


def test_a_remap_stores_the_new_schedules_simulation(member, fan):
    member.post(reverse("heft4k:whatif", args=[fan.pk]), {"node": "node1"})
    new = Schedule.objects.exclude(pk=fan.pk).get(application=fan.application)
    assert ScheduleSimulation.objects.get(schedule=new).baselines
