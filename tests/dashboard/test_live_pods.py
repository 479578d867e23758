"""Live pod state in the pages: the small JSON views the shared partial polls (apps/ui/live.py) on the
schedule, placement and RT cluster pages, fleet-scoped, and the table following it in a real browser."""

import pytest
from django.utils import timezone

from apps.jobs.services import start_job
from apps.realtime.models import RTPod
from apps.scheduling.kinds import SchedulingJob
from apps.scheduling.models import Schedule
from tests.containers.test_pages import autoware, placed  # noqa: F401
from tests.dashboard.test_browser import browser, log_in, page  # noqa: F401
from tests.services.test_celery_worker import make_app

pytestmark = pytest.mark.django_db


def cluster_schedule(fleet, cluster) -> Schedule:
    app = make_app(fleet, 30)
    job = start_job(SchedulingJob.SCHEDULE, fleet, {"application": app.pk, "algorithm": "heft", "cluster": cluster.pk})
    assert job.state == "succeeded", job.error
    return Schedule.objects.get(job=job)


def push_two(schedule: Schedule):
    """Two assignments as the push and the watcher leave them: one running where planned, one elsewhere."""
    first, second = schedule.assignments.order_by("start")[:2]
    other = next(n for n in ("node0", "node1", "node2", "node3") if n != second.processor)
    now = timezone.now()
    first.__class__.objects.filter(pk=first.pk).update(
        pod_name="t-a", pod_phase="Running", pod_node=first.processor, pod_event="Started: container started",
        pod_state_at=now,
    )  # fmt: skip
    second.__class__.objects.filter(pk=second.pk).update(
        pod_name="t-b", pod_phase="Pending", pod_node=other, pod_event="Scheduled: bound", pod_state_at=now
    )
    return first, second, other


def test_schedule_live_lists_the_pushed_pods_next_to_the_plan(member, fleet, cluster, other_api, client):
    schedule = cluster_schedule(fleet, cluster)
    url = f"/schedules/{schedule.pk}/live/"
    empty = member.get(url).json()
    assert empty["pods"] == [] and empty["total"] == 0 and "pushed" in empty["empty"]

    first, second, other = push_two(schedule)
    body = member.get(url).json()
    assert body["total"] == 2 and body["phases"] == {"Running": 1, "Pending": 1} and body["moved"] == 1
    by_pod = {p["pod"]: p for p in body["pods"]}
    assert by_pod["t-a"]["planned"] == by_pod["t-a"]["node"] == first.processor and not by_pod["t-a"]["moved"]
    assert by_pod["t-b"]["planned"] == second.processor and by_pod["t-b"]["node"] == other and by_pod["t-b"]["moved"]
    assert by_pod["t-a"]["event"] == "Started: container started" and by_pod["t-a"]["label"].startswith("task ")

    html = member.get(f"/schedules/{schedule.pk}/").content.decode()
    assert f'data-live-url="{url}"' in html and "js/live-pods.js" in html


def test_live_views_are_fleet_scoped(client, fleets, cluster, fleet, django_user_model):
    schedule = cluster_schedule(fleet, cluster)
    stranger = django_user_model.objects.create_user("stranger", password="stranger-pass-123")
    fleets[1].members.add(stranger)
    client.force_login(stranger)
    assert client.get(f"/schedules/{schedule.pk}/live/").status_code == 404
    assert client.get(f"/realtime/clusters/{cluster.pk}/live/").status_code == 404
    client.logout()
    assert client.get(f"/schedules/{schedule.pk}/live/").status_code == 302  # to the login page


def test_placement_live_shows_each_deployments_pod(member, placed):  # noqa: F811
    name = placed.containers["containers"][0]["name"]
    url = f"/ros/placements/{placed.pk}/live/"
    assert member.get(url).json()["pods"] == []
    placed.deployments.create(
        container=name, node="node1", deployment=f"{name}-d", namespace="continuum", state="applied",
        pod_name=f"{name}-d-123", pod_phase="Running", pod_node="node2", pod_event="Pulled: image present",
        pod_state_at=timezone.now(),
    )  # fmt: skip
    body = member.get(url).json()
    assert body["total"] == 1 and body["moved"] == 1
    (pod,) = body["pods"]
    assert pod["label"] == f"container {name}" and pod["planned"] == "node1" and pod["node"] == "node2"
    assert f'data-live-url="{url}"' in member.get(f"/ros/placements/{placed.pk}/").content.decode()


def test_rt_cluster_live_shows_its_rt_pods(member, cluster):
    RTPod.objects.create(cluster=cluster, namespace="rt", name="gone", node="node0", deleted_at=timezone.now())
    RTPod.objects.create(
        cluster=cluster, namespace="rt", name="slam-0", node="node1", phase="Running", criticality="A",
        pod_event="Started: container started", pod_state_at=timezone.now(),
    )  # fmt: skip
    body = member.get(f"/realtime/clusters/{cluster.pk}/live/").json()
    assert body["total"] == 1  # the deleted pod is not shown
    (pod,) = body["pods"]
    assert pod["pod"] == "rt/slam-0" and pod["phase"] == "Running" and pod["node"] == "node1"
    assert "(A)" in pod["label"] and pod["event"] == "Started: container started"
    html = member.get(f"/realtime/clusters/{cluster.pk}/").content.decode()
    assert f'data-live-url="/realtime/clusters/{cluster.pk}/live/"' in html


@pytest.mark.browser
@pytest.mark.django_db(transaction=True)
def test_schedule_page_follows_pod_phases_without_a_reload(page, live_server, operator, fleet, cluster):  # noqa: F811
    schedule = cluster_schedule(fleet, cluster)
    first, _, _ = push_two(schedule)
    log_in(page, live_server)
    page.goto(f"{live_server.url}/schedules/{schedule.pk}/")
    row = page.locator("section.live-pods tr[data-pod='t-a']")
    row.wait_for()
    assert "Running" in row.inner_text() and "Started: container started" in row.inner_text()
    assert page.locator("section.live-pods tr.moved").count() == 1  # off its planned node, marked
    page.evaluate("window.notReloaded = true")

    first.__class__.objects.filter(pk=first.pk).update(
        pod_phase="Failed", pod_event="BackOff: back-off restarting failed container", pod_state_at=timezone.now()
    )
    page.wait_for_function(
        "document.querySelector(\"section.live-pods tr[data-pod='t-a']\").textContent.includes('BackOff')"
        " && window.notReloaded === true"
    )
    assert "Failed" in row.inner_text()
    assert page.errors == []
