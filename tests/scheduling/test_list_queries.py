"""The Schedules list page never reads a large column (issue 13): with 1000-task schedules the task-count query
grouped by every column, the DAG JSON included, and the page did not answer. The page's SQL names no JSON or
text column of the models it shows (except the platform's processor count, computed inside the database), and
its number of queries does not grow with the number of schedules."""

import re

import pytest
from django.db import connection, models
from django.test.utils import CaptureQueriesContext
from django.urls import reverse

from apps.clusters.models import Cluster
from apps.scheduling.models import Assignment, Schedule
from apps.tenancy.models import Fleet
from apps.workloads.models import Application
from tests.conftest import make_application

pytestmark = pytest.mark.django_db

MODELS = [Schedule, Application, Cluster, Fleet]


def large_columns() -> set[str]:
    """``"table"."column"`` of every JSON or text field of the models the list shows."""
    q = connection.ops.quote_name
    return {
        f"{q(m._meta.db_table)}.{q(f.column)}"
        for m in MODELS
        for f in m._meta.concrete_fields
        if isinstance(f, models.JSONField | models.TextField)
    }


def make_schedules(app, cluster, n: int, tasks: int = 4) -> None:
    for i in range(n):
        platform = {"processors": [{"id": f"p{k}"} for k in range(i % 3 + 1)], "links": []}
        s = Schedule.objects.create(
            fleet=app.fleet,
            application=app,
            cluster=cluster if i % 2 else None,
            platform=platform,
            algorithm="heft",
            makespan=10.0 + i,
            metrics={"padding": "x" * 1000},
        )
        Assignment.objects.bulk_create(
            Assignment(schedule=s, task=f"t{k}", processor="p0", start=k, finish=k + 1) for k in range(tasks + i)
        )


def list_page(client):
    with CaptureQueriesContext(connection) as ctx:
        response = client.get(reverse("scheduling:schedules"))
    assert response.status_code == 200
    return response, [q["sql"] for q in ctx.captured_queries]


def test_the_schedule_list_reads_no_large_column_and_a_constant_number_of_queries(member, fleet):
    app = make_application(fleet)
    cluster = Cluster.objects.create(fleet=fleet, name="c1", description="d" * 1000)
    make_schedules(app, cluster, 3)
    response, few = list_page(member)
    make_schedules(app, cluster, 7)
    response, many = list_page(member)
    assert len(response.context["page"]) == 10

    large = large_columns()
    assert '"workloads_application"."dag"' in large and '"scheduling_schedule"."platform"' in large
    for sql in many:
        # The processor count reads the platform inside jsonb_*/json_* functions; nothing else may name it.
        rest = re.sub(r"jsonb?_\w+\([^()]*\)", "", sql)
        named = [c for c in large if c in rest]
        assert not named, (named, sql)
    assert len(many) == len(few), "\n".join(many)

    page = response.content.decode()
    for s in response.context["page"]:  # the counts are right
        i = round(s.makespan - 10)
        assert s.task_count == Assignment.objects.filter(schedule=s).count() == 4 + i
        assert s.processor_count == i % 3 + 1
        if s.cluster_id is None:
            assert f"{i % 3 + 1} processors" in page


def test_a_platform_without_a_processor_list_shows_zero(member, fleet):
    app = make_application(fleet)
    Schedule.objects.create(fleet=fleet, application=app, platform={"processors": 3}, algorithm="heft", makespan=1)
    response, _ = list_page(member)
    [s] = response.context["page"]
    assert not s.processor_count and s.task_count == 0  # NULL on PostgreSQL, 0 on SQLite
    assert "0 processors" in response.content.decode()
