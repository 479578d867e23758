"""How a stored violation reaches RT-Kube's reconcile worker (issue 15): the ``rt_reconcile`` message goes to the
RT queue of its own (``CONTINUUM_RT_QUEUE``), only once the reports are committed, with the report row ids and
its publish time; a plain worker consumes both queues (``CELERY_TASK_QUEUES``)."""

import base64
import json

import pytest
import redis
from django.conf import settings

from apps.realtime.tasks import queue_reconcile
from tests.services.conftest import celery_broker, redis_url  # noqa: F401 - fixtures

pytestmark = pytest.mark.django_db


@pytest.fixture
def rt_queue(celery_broker, redis_url):  # noqa: F811 - the fixtures imported above
    """The RT queue's list in this test's Redis, emptied before and after."""
    conn = redis.Redis.from_url(redis_url)
    conn.delete(settings.CONTINUUM_RT_QUEUE)
    yield conn
    conn.delete(settings.CONTINUUM_RT_QUEUE)


def test_the_reconcile_is_published_after_the_commit_to_the_rt_queue(rt_cluster, rt_queue,
                                                                     django_capture_on_commit_callbacks):  # fmt: skip
    queue = settings.CONTINUUM_RT_QUEUE
    with django_capture_on_commit_callbacks() as callbacks:
        assert queue_reconcile(rt_cluster, [41, 42]) == []
        assert rt_queue.llen(queue) == 0  # inside the transaction: a worker could not see the rows yet
    assert len(callbacks) == 1 and rt_queue.llen(queue) == 0
    callbacks[0]()  # the commit
    assert rt_queue.llen(queue) == 1
    message = json.loads(rt_queue.rpop(queue))
    assert message["headers"]["task"] == "continuum.rt_reconcile"
    args, kwargs, _ = json.loads(base64.b64decode(message["body"]))
    assert args == [rt_cluster.pk, [41, 42]]
    assert isinstance(kwargs["queued_at"], float)


def test_a_plain_worker_consumes_every_queue_and_rt_tasks_and_sweeps_have_queues_of_their_own():
    from continuum.celery import app

    assert settings.CONTINUUM_RT_QUEUE != settings.CELERY_TASK_DEFAULT_QUEUE
    assert {q.name for q in settings.CELERY_TASK_QUEUES} == {settings.CELERY_TASK_DEFAULT_QUEUE,
                                                             settings.CONTINUUM_RT_QUEUE,
                                                             settings.CONTINUUM_SWEEP_QUEUE}  # fmt: skip
    route = app.amqp.router.route
    assert route({}, "continuum.rt_reconcile")["queue"].name == settings.CONTINUUM_RT_QUEUE
    assert route({}, "continuum.rt_warm")["queue"].name == settings.CONTINUUM_RT_QUEUE
    # The periodic safety sweeps on a queue of their own, which no backlog of jobs delays (issue 25), and dropped
    # when not run within their period (the next one does the same work).
    for task in ("continuum.rt_reconcile_overdue", "continuum.rt_lift_taints", "continuum.recover_lost_jobs"):
        assert route({}, task)["queue"].name == settings.CONTINUUM_SWEEP_QUEUE
    for entry in settings.CELERY_BEAT_SCHEDULE.values():
        assert route({}, entry["task"])["queue"].name == settings.CONTINUUM_SWEEP_QUEUE
        assert entry["options"]["expires"] == entry["schedule"]
    assert route({}, "continuum.run_job")["queue"].name == settings.CELERY_TASK_DEFAULT_QUEUE


def test_the_endpoint_reads_the_cluster_and_its_nodes_in_one_query(api, rt_cluster):
    from django.db import connection
    from django.test.utils import CaptureQueriesContext

    report = {"node": "node3", "containerName": "cam", "missedDeadlinesPeriod": 1, "missedDeadlinesTotal": 1}
    batch = {"cluster": rt_cluster.pk, "reports": [report]}
    with CaptureQueriesContext(connection) as queries:
        response = api.post("/api/v1/rt-reports/", batch, format="json")
    assert response.status_code == 201, response.data
    [lookup] = [q["sql"] for q in queries if 'FROM "clusters_cluster"' in q["sql"]]
    assert '"clusters_computenode"' in lookup  # the nodes come with the cluster ...
    assert not [q for q in queries if q["sql"].lstrip().startswith('SELECT "clusters_computenode"')]  # ... only
    # A node the cluster lacks is still a 400 naming the report, and nothing is stored.
    batch["reports"][0]["node"] = "elsewhere"
    response = api.post("/api/v1/rt-reports/", batch, format="json")
    assert response.status_code == 400
    assert "reports[0]: node 'elsewhere' is not a node of cluster" in str(response.data["reports"])
