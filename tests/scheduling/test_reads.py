"""Reading a large schedule (issue 29): the detail counts no rows, keyset pages walk every assignment once in
order (filters kept), and the export streams every assignment as CSV or JSON lines."""

import csv
import io
import json

import pytest
from django.db import connection
from django.test.utils import CaptureQueriesContext

from apps.scheduling.models import Schedule
from apps.scheduling.serializers import MAX_INLINE_ASSIGNMENTS
from continuum.engine.core.schedule import Assignment as EngineAssignment
from continuum.engine.core.schedule import Schedule as EngineSchedule
from continuum.engine.device.generators import related_platform

pytestmark = pytest.mark.django_db


@pytest.fixture
def big(application):
    # ties in start on purpose: the keyset order breaks them by processor, task and frame
    rows = [EngineAssignment(f"t{i % 700}", f"p{i % 3}", float(i // 4), i // 4 + 1.0, frame=i // 700)
            for i in range(MAX_INLINE_ASSIGNMENTS + 400)]  # fmt: skip
    rows.append(EngineAssignment('q"uote,comma\nline', "p0", 0.0, 1.0))
    rows.append(EngineAssignment("back\\slash\t\\\\two", "p1", 0.0, 1.0))
    return Schedule.store(EngineSchedule("heft", rows), application=application, platform=related_platform(3))


def test_the_detail_counts_no_rows(api, big):
    with CaptureQueriesContext(connection) as queries:
        data = api.get(f"/api/v1/schedules/{big.pk}/").data
    assert data["assignment_count"] == MAX_INLINE_ASSIGNMENTS + 402 and not data["assignments_complete"]
    assert not [q for q in queries if "COUNT(" in q["sql"].upper()]


def test_keyset_pages_walk_every_assignment_once_in_order(api, big):
    url = f"/api/v1/schedules/{big.pk}/assignments/?cursor=&limit=150"
    seen, pages = [], 0
    while url:
        response = api.get(url)
        assert response.status_code == 200, response.data
        assert "count" not in response.data
        seen += [(a["start"], a["processor"], a["task"], a["frame"]) for a in response.data["results"]]
        url, pages = response.data["next"], pages + 1
    assert len(seen) == MAX_INLINE_ASSIGNMENTS + 402 == len(set(seen)) and seen == sorted(seen)
    assert pages == 10
    filtered = api.get(f"/api/v1/schedules/{big.pk}/assignments/?cursor=&processor=p1&limit=1000").data
    assert {a["processor"] for a in filtered["results"]} == {"p1"} and filtered["next"] is None
    for bad in ("nonsense", "WzEsMl0", "WyJ4IiwicCIsInQiLDBd"):  # not base64 json, [1,2], ["x","p","t",0]
        response = api.get(f"/api/v1/schedules/{big.pk}/assignments/?cursor={bad}")
        assert response.status_code == 400 and "cursor" in response.data


def test_the_export_streams_every_assignment(api, big):
    response = api.get(f"/api/v1/schedules/{big.pk}/export/")
    assert response.status_code == 200 and response["Content-Type"].startswith("text/csv") and response.streaming
    rows = list(csv.DictReader(io.StringIO(b"".join(response.streaming_content).decode())))
    assert len(rows) == MAX_INLINE_ASSIGNMENTS + 402
    assert 'q"uote,comma\nline' in {r["task"] for r in rows}
    keys = [(float(r["start"]), r["processor"], r["task"], int(r["frame"])) for r in rows]
    assert keys == sorted(keys)
    response = api.get(f"/api/v1/schedules/{big.pk}/export/?as=jsonl")
    lines = b"".join(response.streaming_content).decode().splitlines()
    objects = [json.loads(line) for line in lines]
    assert len(objects) == MAX_INLINE_ASSIGNMENTS + 402 and objects[0]["placement"] == "not_pushed"
    assert {"back\\slash\t\\\\two", 'q"uote,comma\nline'} <= {o["task"] for o in objects}
    assert {o["task"] for o in objects} == {r["task"] for r in rows}
    assert [(o["start"], o["processor"], o["task"], o["frame"]) for o in objects] == keys
    assert api.get(f"/api/v1/schedules/{big.pk}/export/?as=xml").status_code == 400
