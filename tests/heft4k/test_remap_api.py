"""HEFT4K remapping through the API and the jobs: what-if vs apply, the stored event, validation, scoping.

The cluster here is model-only (no kubeconfig); what Kubernetes sees is tested in tests/kube/test_heft4k.py.
"""

import pytest

from apps.heft4k.kinds import Heft4kJob
from apps.heft4k.models import RemapEvent
from apps.jobs.models import Job
from apps.scheduling.models import Schedule
from continuum.engine.heft4k.remap import remap as engine_remap

from .fan import heft4k_schedule, nodes_of, run

pytestmark = pytest.mark.django_db


def expected(schedule, failed, threshold=0.2):
    """What the engine's Algorithm 2 says for the same stored schedule (the product must agree)."""
    return engine_remap(
        schedule.to_engine(), schedule.application.graph, schedule.engine_platform(), failed, threshold=threshold
    )


def remap_url(schedule) -> str:
    return f"/api/v1/schedules/{schedule.pk}/remap/"


def test_what_if_stores_the_remap_and_the_new_schedule_and_pushes_nothing(api, cluster):
    schedule = heft4k_schedule(api, cluster)
    before = nodes_of(schedule)
    on_node1 = sorted(t for t, n in before.items() if n == "node1")
    assert len(on_node1) == 4

    job = run(api, remap_url(schedule), {"fail": ["node1"], "what_if": True})
    assert job["state"] == "succeeded", job
    event = RemapEvent.objects.get()
    assert job["result"]["remap"] == event.pk and job["result"]["schedule"] == event.new_schedule_id
    assert job["result_url"] == f"/api/v1/remaps/{event.pk}/"
    truth = expected(schedule, ["node1"])
    assert truth.mode == "partial"
    assert (event.decision, event.trigger, event.status) == ("partial", "what-if", "what-if")
    assert event.failed_nodes == ["node1"]
    assert sorted(event.lost_tasks) == on_node1 == sorted(truth.lost)
    assert sorted(event.moved_tasks) == on_node1  # partial: only the lost tasks move
    assert event.reniced_tasks == [] and event.critical_lost == []
    assert event.lost_share == pytest.approx(truth.lost_share) and 0.15 < event.lost_share <= 0.2
    assert event.threshold == 0.2 and event.reason == truth.reason
    assert event.makespan_before == schedule.makespan
    assert event.makespan_after == pytest.approx(truth.makespan_after)
    assert event.elapsed_ms > 0 and event.pods == [] and event.applied is None
    assert str(event.job_id) == job["id"]

    new = event.new_schedule
    assert new.algorithm == "heft4k" and new.cluster == cluster and new.application == schedule.application
    assert new.makespan == pytest.approx(truth.makespan_after)
    assert [p["id"] for p in new.platform["processors"]] == ["node0", "node2", "node3"]
    after = nodes_of(new)
    assert all(after[t] == before[t] for t in before if t not in on_node1)  # unaffected tasks stay
    assert all(after[t] != "node1" for t in on_node1)
    assert set(new.assignments.values_list("placement", flat=True)) == {"not_pushed"}
    assert new.params["remap"] == "partial" and new.metrics["remap"]["mode"] == "partial"
    assert nodes_of(Schedule.objects.get(pk=schedule.pk)) == before  # the old schedule is unchanged

    data = api.get(f"/api/v1/remaps/{event.pk}/").data
    assert data["decision"] == "partial" and data["can_apply"] is True
    assert data["makespan_change"] == pytest.approx(event.makespan_after / event.makespan_before - 1)
    assert data["schedule"] == schedule.pk and data["new_schedule"] == new.pk
    listed = api.get("/api/v1/remaps/", {"application": schedule.application_id}).data
    assert [r["id"] for r in listed["results"]] == [event.pk]


def test_apply_on_a_model_only_cluster_stores_the_schedule_and_changes_no_pod(api, cluster):
    schedule = heft4k_schedule(api, cluster)
    job = run(api, remap_url(schedule), {"fail": ["node2"]})
    assert job["state"] == "succeeded", job
    event = RemapEvent.objects.get()
    assert (event.trigger, event.status) == ("api", "not-pushed")
    assert event.message == "stored; the cluster has no Kubernetes API, so no pod was changed"
    assert event.applied is not None and event.pods == []
    assert job["result"]["status"] == "not-pushed" and job["result"]["pods_moved"] == 0
    response = api.post(f"/api/v1/remaps/{event.pk}/apply/")
    assert response.status_code == 400
    assert response.data == {
        "non_field_errors": [f"remap {event.pk} is already stored; nothing in Kubernetes to change"]
    }


def test_a_what_if_is_applied_later_and_only_once(api, cluster):
    schedule = heft4k_schedule(api, cluster)
    run(api, remap_url(schedule), {"fail": ["node3"], "what_if": True})
    run(api, remap_url(schedule), {"fail": ["node2"], "what_if": True})
    first, second = RemapEvent.objects.order_by("pk")
    job = run(api, f"/api/v1/remaps/{first.pk}/apply/")
    assert job["state"] == "succeeded", job
    assert job["result"]["remap"] == first.pk
    first.refresh_from_db()
    assert first.status == "not-pushed" and first.trigger == "what-if"
    # A model-only apply changes nothing in Kubernetes, so the other what-if may still be applied.
    assert api.get(f"/api/v1/remaps/{second.pk}/").data["can_apply"] is True
    # Once a remap was applied in Kubernetes, another remap of the same schedule is refused.
    RemapEvent.objects.filter(pk=first.pk).update(status="applied")
    response = api.post(f"/api/v1/remaps/{second.pk}/apply/")
    assert response.status_code == 400
    assert f"schedule {schedule.pk} was already remapped by remap {first.pk}" in response.data["non_field_errors"][0]
    assert api.get(f"/api/v1/remaps/{second.pk}/").data["can_apply"] is False


def test_losing_the_critical_task_forces_a_total_remap(api, cluster):
    schedule = heft4k_schedule(api, cluster)
    assert nodes_of(schedule)["sink"] == "node0"
    job = run(api, remap_url(schedule), {"fail": ["node0"], "what_if": True})
    assert job["state"] == "succeeded", job
    event = RemapEvent.objects.get()
    assert event.decision == "total" and event.critical_lost == ["sink"]
    assert event.reason == "critical task 'sink' was lost"
    assert "node0" not in nodes_of(event.new_schedule).values()
    truth = expected(schedule, ["node0"])
    assert sorted(event.moved_tasks) == sorted(truth.moved)
    # Tasks kept on their node but given another niceness by the new ranks need a new pod too.
    old = {a.task: (a.processor, a.niceness) for a in schedule.assignments.all()}
    new = {a.task: (a.processor, a.niceness) for a in event.new_schedule.assignments.all()}
    assert sorted(event.reniced_tasks) == sorted(t for t in old if old[t][0] == new[t][0] and old[t][1] != new[t][1])
    assert set(event.changed_tasks) == {t for t in old if old[t] != new[t]}


def test_the_threshold_decides_between_partial_and_total(api, cluster):
    schedule = heft4k_schedule(api, cluster)
    assert run(api, remap_url(schedule), {"fail": ["node1"], "what_if": True, "threshold": 0.1})["state"] == "succeeded"
    event = RemapEvent.objects.get()
    assert event.decision == "total" and event.threshold == 0.1
    assert event.reason.startswith("lost rank share 19.") and event.reason.endswith("> threshold 10%")
    assert event.decision == expected(schedule, ["node1"], 0.1).mode


def test_nodes_known_to_be_down_are_failed_too(api, cluster):
    schedule = heft4k_schedule(api, cluster)
    cluster.nodes.filter(name="node2").update(status="NotReady")
    job = run(api, remap_url(schedule), {"fail": ["node1"], "what_if": True})
    assert job["state"] == "succeeded", job
    event = RemapEvent.objects.get()
    assert event.failed_nodes == ["node1", "node2"]
    before = nodes_of(schedule)
    assert sorted(event.lost_tasks) == sorted(t for t, n in before.items() if n in ("node1", "node2"))
    assert not {"node1", "node2"} & set(nodes_of(event.new_schedule).values())


@pytest.mark.parametrize(
    ("body", "field", "message"),
    [
        ({"fail": ["node9"]}, "fail", "unknown node 'node9': schedule {pk} was made on node0, node1, node2, node3"),
        ({"fail": []}, "fail", "This list may not be empty."),
        ({}, "fail", "This field is required."),
        ({"fail": ["node1"], "threshold": 1.5}, "threshold", "Ensure this value is less than or equal to 1.0."),
        (
            {"fail": ["node0", "node1", "node2", "node3"]},
            "fail",
            "no node of schedule {pk} would be left: node0, node1, node2, node3 all fail",
        ),
    ],
)
def test_bad_remap_requests_answer_400_and_store_nothing(api, cluster, body, field, message):
    schedule = heft4k_schedule(api, cluster)
    jobs, schedules = Job.objects.count(), Schedule.objects.count()
    response = api.post(remap_url(schedule), body, format="json")
    assert response.status_code == 400
    assert response.data[field] == [message.format(pk=schedule.pk)]
    assert (Job.objects.count(), Schedule.objects.count(), RemapEvent.objects.count()) == (jobs, schedules, 0)


def test_a_node_without_tasks_has_nothing_to_remap(api, cluster):
    dag = {
        "format": "continuum.dag/v1",
        "name": "pair",
        "tasks": [{"id": "a", "cost": {"cpu": 1}}, {"id": "b", "cost": {"cpu": 1}}],
        "edges": [{"src": "a", "dst": "b", "data": 1}],
    }
    schedule = heft4k_schedule(api, cluster, dag)
    idle = next(n for n in ("node0", "node1", "node2", "node3") if n not in nodes_of(schedule).values())
    response = api.post(remap_url(schedule), {"fail": [idle]}, format="json")
    assert response.status_code == 400
    assert response.data["fail"] == [f"no task of schedule {schedule.pk} runs on {idle}: nothing to remap"]


def test_multi_frame_schedules_are_refused(api, cluster):
    schedule = heft4k_schedule(api, cluster)
    schedule.assignments.filter(task="w00").update(frame=1)
    response = api.post(remap_url(schedule), {"fail": ["node1"]}, format="json")
    assert response.status_code == 400
    assert "several frames" in response.data["schedule"][0]


def test_another_fleet_gets_404_everywhere(api, other_api, cluster):
    schedule = heft4k_schedule(api, cluster)
    run(api, remap_url(schedule), {"fail": ["node1"], "what_if": True})
    event = RemapEvent.objects.get()
    assert other_api.post(remap_url(schedule), {"fail": ["node1"]}, format="json").status_code == 404
    assert other_api.get(f"/api/v1/remaps/{event.pk}/").status_code == 404
    assert other_api.post(f"/api/v1/remaps/{event.pk}/apply/").status_code == 404
    assert other_api.get("/api/v1/remaps/").data["count"] == 0
    assert RemapEvent.objects.count() == 1 and RemapEvent.objects.get().status == "what-if"
    assert api.get("/api/v1/remaps/").data["count"] == 1


def test_a_redelivered_remap_job_does_not_compute_twice(api, cluster):
    from apps.jobs.registry import HANDLERS

    schedule = heft4k_schedule(api, cluster)
    job = Job.objects.get(pk=run(api, remap_url(schedule), {"fail": ["node1"], "what_if": True})["id"])
    schedules = Schedule.objects.count()
    result, url = HANDLERS["remap"](job, lambda percent, message: None)  # the worker died; it runs again
    event = RemapEvent.objects.get()
    assert result == job.result and url == f"/api/v1/remaps/{event.pk}/"
    assert Schedule.objects.count() == schedules


def test_remap_jobs_reject_bad_arguments(fleet):
    from apps.jobs.services import start_job

    job = start_job(Heft4kJob.REMAP, fleet, {"schedule": "x", "fail": ["n"]})
    assert job.state == "failed" and job.error == "argument 'schedule' must be the id of a schedule, got 'x'"
    job = start_job(Heft4kJob.REMAP, fleet, {"schedule": 999999, "fail": ["n"]})
    assert job.state == "failed" and job.error == "schedule 999999 does not exist"
    job = start_job(Heft4kJob.REMAP_APPLY, fleet, {"remap": 999999})
    assert job.state == "failed" and job.error == "remap 999999 does not exist"


def test_event_figures():
    event = RemapEvent(
        makespan_before=20.0,
        makespan_after=25.0,
        moved_tasks=["a", "b"],
        reniced_tasks=["c"],
        pods=[{"task": "a", "created": True}, {"task": "b", "created": False}, {"task": "c", "created": True}],
    )
    assert event.makespan_change == pytest.approx(0.25)
    assert event.changed_tasks == ["a", "b", "c"]
    assert event.pods_moved == 2
