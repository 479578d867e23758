"""The push job's write-back (issue 29): one set-based statement that changes only the rows whose placement,
message or pod name differ, so a re-push that changes nothing writes nothing."""

import pytest
from django.db import connection
from django.test.utils import CaptureQueriesContext

from apps.scheduling.models import Assignment, Schedule
from continuum.engine.core.schedule import Assignment as EngineAssignment
from continuum.engine.core.schedule import Schedule as EngineSchedule
from continuum.engine.device.generators import related_platform

pytestmark = pytest.mark.django_db


def test_only_changed_rows_are_written_in_one_statement(application, monkeypatch):
    rows = [EngineAssignment(f"t{i}", f"p{i % 3}", float(i), i + 0.5) for i in range(250)]
    schedule = Schedule.store(EngineSchedule("heft", rows), application=application, platform=related_platform(3))
    mine = list(schedule.assignments.order_by("task"))
    other = Schedule.store(EngineSchedule("heft", rows[:5]), application=application, platform=related_platform(3))
    for i, a in enumerate(mine):
        a.placement = Assignment.Placement.BOUND if i % 7 else Assignment.Placement.FAILED
        a.placement_message = "" if i % 7 else f"node p{i % 3} is NotReady: it's \"gone\"; -- 'quoted'"
        a.pod_name = f"app-t{i}"
    with CaptureQueriesContext(connection) as queries:
        assert Assignment.store_placements(mine) == 250
    if connection.vendor == "postgresql":
        assert len(queries) == 1 and "FROM (VALUES" in queries[0]["sql"]
    back = {a.pk: a for a in schedule.assignments.all()}
    for want in mine:
        got = back[want.pk]
        assert (got.placement, got.placement_message, got.pod_name) == (
            want.placement,
            want.placement_message,
            want.pod_name,
        )
    assert set(other.assignments.values_list("placement", flat=True)) == {"not_pushed"}  # untouched
    if connection.vendor == "postgresql":
        assert Assignment.store_placements(mine) == 0  # nothing differs: nothing written
        mine[3].placement_message = "changed"
        monkeypatch.setattr(Assignment, "PLACEMENT_BATCH", 100)  # three statements, one row changed
        assert Assignment.store_placements(mine) == 1
        assert Assignment.objects.get(pk=mine[3].pk).placement_message == "changed"
    assert Assignment.store_placements([]) == 0
