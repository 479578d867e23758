"""Reading a large stored schedule through the API, the requests a user makes side by side (issue 29).

Stores one schedule of ``--rows`` assignments (10,000 tasks x 10 frames by default) in a throw-away PostgreSQL
database (``<DATABASE_URL's name>_reads_bench``, dropped at the end), then times with the test client, CPU and
wall: the schedule's detail; reading every assignment page by page with ``limit``/``offset`` (the reference:
each page scans the rows before it and counts all of them) and with keyset pages (``cursor``); the export in
one streamed response, CSV and JSON lines, in rows/s against the goal of 50,000; and the database alone
(``COPY`` of the same rows to nowhere) as the floor. Prints the load average.

    python benchmarks/schedule_reads.py [--rows 100000] [--page 1000]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from benchmarks._bench import loadavg, table, throwaway_database

GOAL_ROWS_S = 50_000


def clock(fn):
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rows", type=int, default=100_000)
    p.add_argument("--page", type=int, default=1000)
    args = p.parse_args()
    with throwaway_database("_reads_bench"):
        run(args)


def run(args: argparse.Namespace) -> None:
    import django

    django.setup()
    from django.contrib.auth import get_user_model
    from django.core.management import call_command
    from django.db import connection, transaction
    from django.test import Client
    from django.test.utils import setup_test_environment

    from apps.scheduling.models import Schedule
    from apps.tenancy.models import Fleet
    from apps.workloads.models import Application
    from continuum.engine.core.schedule import Assignment
    from continuum.engine.core.schedule import Schedule as EngineSchedule
    from continuum.engine.device.generators import related_platform

    setup_test_environment()
    call_command("migrate", verbosity=0)
    user = get_user_model().objects.create_user("bench-reads", password="bench-pass-123")
    fleet, _ = Fleet.objects.get_or_create(slug="reads-bench", defaults={"name": "reads-bench"})
    fleet.members.add(user)
    client = Client()
    client.force_login(user)
    app = Application.objects.create(fleet=fleet, name="reads", dag={})
    frames = 10
    tasks = max(1, args.rows // frames)
    rows = [Assignment(f"t{i}", f"p{i % 8}", float(i + f * tasks), i + f * tasks + 1.0, frame=f)
            for f in range(frames) for i in range(tasks)]  # fmt: skip
    with transaction.atomic():
        schedule = Schedule.store(EngineSchedule("heft", rows), application=app, platform=related_platform(8))
    n = len(rows)
    print(f"one schedule of {n} assignments; load average {loadavg()}", flush=True)

    def get(url: str):
        response = client.get(url)
        assert response.status_code == 200, (url, response.status_code)
        return response

    api = f"/api/v1/schedules/{schedule.pk}"
    out = []
    _, wall, cpu = clock(lambda: get(f"{api}/"))
    out.append(["detail GET /schedules/{id}/", wall, cpu, "-"])

    def offset_all() -> int:
        seen = 0
        for offset in range(0, n, args.page):
            seen += len(get(f"{api}/assignments/?limit={args.page}&offset={offset}").json()["results"])
        return seen

    def keyset_all() -> int:
        seen, url = 0, f"{api}/assignments/?cursor=&limit={args.page}"
        while url:
            body = get(url).json()
            seen += len(body["results"])
            url = body["next"] and body["next"].replace("http://testserver", "")
        return seen

    seen, wall, cpu = clock(offset_all)
    out.append([f"every page, limit/offset ({n // args.page} pages)", wall, cpu, f"{seen / wall:,.0f}"])
    seen_k, wall, cpu = clock(keyset_all)
    out.append([f"every page, keyset cursor ({n // args.page} pages)", wall, cpu, f"{seen_k / wall:,.0f}"])
    _, wall1, cpu1 = clock(lambda: get(f"{api}/assignments/?limit={args.page}&offset=0"))
    _, wall2, cpu2 = clock(lambda: get(f"{api}/assignments/?limit={args.page}&offset={n - args.page}"))
    out.append(["  offset: first page / last page", f"{wall1:.3f} / {wall2:.3f}", f"{cpu1:.3f} / {cpu2:.3f}", "-"])
    rates = {}
    for kind in ("csv", "jsonl"):
        response, wall, cpu = clock(lambda kind=kind: get(f"{api}/export/?as={kind}"))
        body, wall2, cpu2 = clock(lambda response=response: b"".join(response.streaming_content))
        lines = body.count(b"\n") - (1 if kind == "csv" else 0)
        rates[kind] = lines / (wall + wall2)
        out.append([f"export as={kind} ({len(body) / 2**20:.1f} MiB)", wall + wall2, cpu + cpu2,
                    f"{rates[kind]:,.0f}"])  # fmt: skip

    def floor() -> int:
        size = 0
        with (
            connection.cursor() as cursor,
            cursor.cursor.copy(
                "COPY (SELECT * FROM scheduling_assignment WHERE schedule_id = %s) TO STDOUT", [schedule.pk]
            ) as copy,
        ):
            for chunk in copy:
                size += len(chunk)
        return size

    _, wall, cpu = clock(floor)
    out.append(["floor: COPY of the rows, no HTTP", wall, cpu, f"{n / wall:,.0f}"])
    print(table(["request", "wall s", "CPU s", "rows/s"], out))
    print(f"keyset pages read {seen_k} rows (offset {seen}); goal >= {GOAL_ROWS_S:,} rows/s for the export: "
          f"CSV {rates['csv']:,.0f}, JSON lines {rates['jsonl']:,.0f}; load average {loadavg()}")  # fmt: skip


if __name__ == "__main__":
    main()
