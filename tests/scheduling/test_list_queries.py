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
from continuum.engine.core.platform import Platform
from continuum.engine.core.schedule import Assignment as EngineAssignment
from continuum.engine.core.schedule import Schedule as EngineSchedule
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
    """``n`` schedules stored as a job stores them; schedule ``i`` has ``tasks + i`` assignments (so its
    makespan is ``tasks + i``) on ``i % 3 + 1`` processors."""
    for i in range(n):
        platform = Platform.from_dict({"processors": [{"id": f"p{k}"} for k in range(i % 3 + 1)], "links": []})
        rows = [EngineAssignment(f"t{k}", "p0", k, k + 1) for k in range(tasks + i)]
        engine = EngineSchedule("heft", rows, metrics={"padding": "x" * 1000})
        Schedule.store(engine, application=app, platform=platform, cluster=cluster if i % 2 else None)


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
        i = round(s.makespan - 4)
        assert s.task_count == Assignment.objects.filter(schedule=s).count() == 4 + i
        assert s.processor_count == i % 3 + 1
        if s.cluster_id is None:
            assert f"{i % 3 + 1} processors" in page


def test_a_platform_without_a_processor_list_shows_zero(member, fleet):
    app = make_application(fleet)
    Schedule.objects.create(fleet=fleet, application=app, platform={"processors": 3}, algorithm="heft", makespan=1)
    response, _ = list_page(member)
    [s] = response.context["page"]
    assert not s.processor_count and s.task_count == 0  # processor_count: NULL on PostgreSQL, 0 on SQLite
    assert "0 processors" in response.content.decode()


def test_the_list_shows_each_schedules_stored_count_and_time_unit(member, fleet):
    """The count and the unit are stored with the schedule (no row count or DAG read per listed schedule)."""
    app = make_application(fleet)
    app.dag = {**app.dag, "time_unit": "us"}
    app.save(update_fields=["dag"])
    make_schedules(app, None, 1, tasks=7)
    response, sql = list_page(member)
    [s] = response.context["page"]
    assert (s.task_count, s.time_unit) == (7, "us")
    assert "7 us" in response.content.decode()
    assert not any('"scheduling_assignment"' in q for q in sql)
