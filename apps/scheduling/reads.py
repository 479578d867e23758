"""Reading a large schedule's assignments (issue 29): keyset pages and one streamed export.

* **Keyset pages**: ``GET /api/v1/schedules/{id}/assignments/?cursor=`` (empty for the first page, then the
  ``next`` link's cursor) in the order (start, processor, task, frame), unique within a schedule, read with a row
  comparison the index ``assignment_keyset`` answers: each page costs the same whatever its depth (``offset``
  scans and drops every row before it) and no page counts every row.
* **Export**: ``GET /api/v1/schedules/{id}/export/?as=csv|jsonl``, every assignment in one streamed response in
  the same order, both from PostgreSQL's ``COPY ... TO STDOUT`` (the JSON built by the database); memory does
  not grow with the schedule.
"""

from __future__ import annotations

import base64
import binascii
import csv
import io
import json
from collections.abc import Iterator
from datetime import datetime
from typing import Any

from django.db import connection
from django.db.models import QuerySet

from .models import Assignment

#: The export's and the keyset's columns and order.
COLUMNS = ("task", "frame", "processor", "core", "start", "finish", "niceness", "placement", "placement_message",
           "pod_name", "pod_phase", "pod_node", "pod_event", "pod_state_at")  # fmt: skip
ORDER = ("start", "processor", "task", "frame")
CHUNK = 5000


class BadCursor(ValueError):
    pass


def encode_cursor(row: Assignment) -> str:
    key = [row.start, row.processor, row.task, row.frame]
    return base64.urlsafe_b64encode(json.dumps(key, separators=(",", ":")).encode()).decode().rstrip("=")


def decode_cursor(text: str) -> tuple[float, str, str, int]:
    """The key a cursor names; :class:`BadCursor` for anything this module did not write."""
    try:
        raw = base64.urlsafe_b64decode(text + "=" * (-len(text) % 4))
        start, processor, task, frame = json.loads(raw)
    except (binascii.Error, ValueError, TypeError, UnicodeDecodeError) as exc:
        raise BadCursor("not a cursor of this endpoint") from exc
    ok = (
        isinstance(start, int | float)
        and not isinstance(start, bool)
        and isinstance(processor, str)
        and isinstance(task, str)
        and isinstance(frame, int)
        and not isinstance(frame, bool)
        and 0 <= frame < 2**31
        and abs(start) < 1e300
    )
    if not ok:
        raise BadCursor("not a cursor of this endpoint")
    return float(start), processor, task, frame


def keyset_page(queryset: QuerySet, cursor: str, limit: int) -> tuple[list[Assignment], str | None]:
    """(up to ``limit`` rows after ``cursor`` ("" = from the first), the next page's cursor or None)."""
    qs = queryset.order_by(*ORDER)
    if cursor:
        table = connection.ops.quote_name(Assignment._meta.db_table)
        cols = ", ".join(f"{table}.{connection.ops.quote_name(c)}" for c in ORDER)
        qs = qs.extra(where=[f"({cols}) > (%s, %s, %s, %s)"], params=list(decode_cursor(cursor)))
    rows = list(qs[: limit + 1])
    more = len(rows) > limit
    rows = rows[:limit]
    return rows, (encode_cursor(rows[-1]) if more and rows else None)


def export_csv(schedule_id: int) -> Iterator[bytes]:
    """Every assignment of the schedule as CSV with a header, in chunks as the database sends them."""
    if connection.vendor == "postgresql":
        q = connection.ops.quote_name
        sql = (
            f"COPY (SELECT {', '.join(q(c) for c in COLUMNS)} FROM {q(Assignment._meta.db_table)} "
            f"WHERE schedule_id = %s ORDER BY {', '.join(q(c) for c in ORDER)}) TO STDOUT WITH (FORMAT csv, HEADER)"
        )
        with connection.cursor() as cursor, cursor.cursor.copy(sql, [schedule_id]) as copy:
            yield from (bytes(chunk) for chunk in copy)
        return
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(COLUMNS)
    for i, row in enumerate(_rows(schedule_id)):
        writer.writerow(["" if v is None else v for v in row])
        if i % CHUNK == CHUNK - 1:
            yield buf.getvalue().encode()
            buf.seek(0)
            buf.truncate()
    yield buf.getvalue().encode()


def export_jsonl(schedule_id: int) -> Iterator[bytes]:
    """Every assignment as one JSON object a line: on PostgreSQL each line is built by the database
    (``row_to_json``) and sent by ``COPY``, whose text format doubles every backslash (the one
    character it escapes that JSON text holds: control characters are escaped by the JSON already), undone
    here per row (one CopyData message per row, so never across a chunk). Elsewhere built in chunks here."""
    if connection.vendor == "postgresql":
        q = connection.ops.quote_name
        # row_to_json writes compact JSON (json_build_object puts spaces around every colon and comma).
        sql = (
            f"COPY (SELECT row_to_json(r) FROM (SELECT {', '.join(q(c) for c in COLUMNS)} "
            f"FROM {q(Assignment._meta.db_table)} WHERE schedule_id = %s "
            f"ORDER BY {', '.join(q(c) for c in ORDER)}) AS r) TO STDOUT"
        )
        with connection.cursor() as cursor, cursor.cursor.copy(sql, [schedule_id]) as copy:
            batch: list[bytes] = []
            for row in copy:
                batch.append(bytes(row).replace(b"\\\\", b"\\"))
                if len(batch) >= CHUNK:
                    yield b"".join(batch)
                    batch = []
            if batch:
                yield b"".join(batch)
        return
    lines: list[str] = []
    dumps = json.JSONEncoder(separators=(",", ":"), default=_default).encode
    for row in _rows(schedule_id):
        lines.append(dumps(dict(zip(COLUMNS, row, strict=True))))
        if len(lines) >= CHUNK:
            yield ("\n".join(lines) + "\n").encode()
            lines = []
    if lines:
        yield ("\n".join(lines) + "\n").encode()


def _rows(schedule_id: int) -> Iterator[tuple]:
    qs = Assignment.objects.filter(schedule_id=schedule_id).order_by(*ORDER).values_list(*COLUMNS)
    return qs.iterator(chunk_size=CHUNK)


def _default(value: Any) -> Any:
    if isinstance(value, datetime):
        return value.isoformat()
    raise TypeError(f"{type(value).__name__} is not JSON")
