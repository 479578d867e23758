"""The worst input each write endpoint accepts, at its body limit (issue 25): time per byte and worst request time.

Issue 25 found a 919 KiB ``placements/run`` body holding a web thread 58-69 s (a quadratic duplicate-name check).
Every endpoint's body is now bounded before parsing (``document_actions``: ``limits.upload_bytes``, others
``limits.body_bytes``; apps/tenancy/bounds.py) and every check is meant to be linear; this measures it. For each
write endpoint of the OpenAPI schema it sends, through Django's test client in this process (every middleware,
authentication, parsing and validation included; jobs are queued to a broker in files that nothing consumes, so
only the request is timed):

- generic hostile shapes filled to the endpoint's limit: one long string field (``long-string``), an object of
  many keys (``many-keys``), brackets nested to the limit (``deep``), a form body of many fields (``form``),
  and a body one byte over the limit (``over``: must be a 413, refused unread);
- for the endpoints whose checks scale with a document, the largest *valid-looking* document their item limits
  allow, padded to the body limit when it is smaller (``document``): placements with ``limits.nodes``
  containers and ``limits.links`` bandwidth entries (the issue's case), a cluster of ``nodes`` x ``links``, a
  DAG of ``tasks`` x ``edges``, STL event and RT report batches.

Printed per endpoint: its limit, the worst shape, its size, wall and CPU time of the request and the CPU time per
byte; then the worst request overall, with the load average (wall time on a shared machine is noisy: the CPU time
is this process's). SQLite in a temporary directory by default; ``--database-url postgres://...`` uses (and
drops) that PostgreSQL database instead.

    python benchmarks/input_limits.py [--database-url URL] [--scale 1.0] [--only SUBSTRING] [--json]

``--scale`` multiplies every body size (0.1 for a quick look; the figures per byte stay comparable).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks._bench import drop_database, loadavg, recreate_database, table  # noqa: E402


def _pad(doc: dict, size: int) -> bytes:
    """``doc`` as JSON, padded with trailing spaces up to ``size`` bytes (JSON ignores them)."""
    body = json.dumps(doc, separators=(",", ":")).encode()
    return body + b" " * max(0, size - len(body))


def _fit(make, size: int, lo: int = 1, hi: int = 1 << 22) -> bytes:
    """The largest ``make(n)`` (JSON bytes, growing about linearly with n) not above ``size``, n in [lo, hi]:
    n estimated from a sample, then lowered 2% at a time until it fits."""
    sample = min(hi, 1000)
    n = min(hi, max(lo, int(size * sample / max(1, len(make(sample))))))
    body = make(n)
    while len(body) > size and n > lo:
        n = max(lo, int(n * 0.98))
        body = make(n)
    return body


# ---- the documents --------------------------------------------------------------------------------------
def placement_doc(cluster: int, lim, size: int) -> bytes:
    n, m = lim.nodes, lim.links
    containers = [{"name": f"container-{i:05d}", "cpu": 0.01, "memory_mib": 1} for i in range(n)]
    bandwidth = [{"a": f"container-{i % n:05d}", "b": f"container-{(i * 7 + 1) % n:05d}", "bytes_per_s": 1}
                 for i in range(m) if i % n != (i * 7 + 1) % n]  # fmt: skip
    doc = {"cluster": cluster, "containers": {"containers": containers, "bandwidth": bandwidth}}
    return _pad(doc, size)


def cluster_doc(lim, size: int, name: str) -> bytes:
    n, m = lim.nodes, lim.links
    nodes = [{"name": f"node-{i:05d}", "cpu": 4, "memory_mib": 8192, "labels": {"zone": "edge"}} for i in range(n)]
    links = [{"src": f"node-{i % n:05d}", "dst": f"node-{(i // n + i + 1) % n:05d}", "bandwidth_mbps": 1000}
             for i in range(m)]  # fmt: skip
    seen, unique = set(), []
    for link in links:
        key = (link["src"], link["dst"])
        if link["src"] != link["dst"] and key not in seen:
            seen.add(key)
            unique.append(link)
    return _pad({"name": name, "format": "continuum.cluster/v1", "nodes": nodes, "links": unique}, size)


def dag_doc(lim, size: int) -> bytes:
    def make(n: int) -> bytes:
        tasks = [{"id": f"t{i}", "cost": {"cpu": 1.5, "gpu": 0.5}} for i in range(n)]
        edges = [{"src": f"t{i}", "dst": f"t{j}", "data": 1} for i in range(n) for j in range(i + 1, min(n, i + 11))]
        return json.dumps({"name": "worst", "dag": {"format": "continuum.dag/v1", "name": "worst", "tasks": tasks,
                                                    "edges": edges[: lim.edges]}}).encode()  # fmt: skip

    return _fit(make, size, 1, lim.tasks) + b""


def events_doc(cluster: int, size: int) -> bytes:
    return _fit(lambda n: json.dumps({"cluster": cluster, "events": [["speed", 1.5, i] for i in range(n)]}).encode(),
                size)  # fmt: skip


def reports_doc(cluster: int, size: int) -> bytes:
    def report(i: int) -> dict:
        return {"node": f"node-{i % 5000:05d}", "containerName": f"c{i}", "missedDeadlinesPeriod": 0,
                "missedDeadlinesTotal": 0}  # fmt: skip

    return _fit(lambda n: json.dumps({"cluster": cluster, "reports": [report(i) for i in range(n)]}).encode(), size)


# ---- the generic shapes ----------------------------------------------------------------------------------
def generic_shapes(size: int, limit: int) -> dict[str, tuple[bytes, str]]:
    json_type, form_type = "application/json", "application/x-www-form-urlencoded"
    return {
        "long-string": (_pad({"name": "x" * (size - 40), "text": "G(x > 0)"}, size)[:size], json_type),
        "many-keys": (_fit(lambda n: json.dumps({f"k{i}": i for i in range(n)}).encode(), size), json_type),
        "deep": (b"[" * size, json_type),
        "form": ("&".join(f"f{i}=1" for i in range(999)).encode().ljust(size, b"x"), form_type),
        "over": (b" " * (limit + 1), json_type),
    }


# ---- the run ---------------------------------------------------------------------------------------------
def run(scale: float, only: str | None) -> dict:
    import django

    os.environ.setdefault("DJANGO_SETTINGS_MODULE", "continuum.settings")
    django.setup()
    from django.core.management import call_command
    from django.test.utils import setup_test_environment
    from drf_spectacular.generators import SchemaGenerator
    from rest_framework.test import APIClient

    from apps.tenancy.bounds import UPLOAD_FRAMING_BYTES
    from apps.tenancy.models import Fleet, FleetToken
    from continuum.engine.core import limits

    setup_test_environment()  # the test client's host, 'testserver', is allowed
    call_command("migrate", verbosity=0)
    from django.contrib.auth import get_user_model

    lim = limits.get()
    fleet = Fleet.objects.create(name="Bench fleet")
    user = get_user_model().objects.create_user("bench-operator", password="bench-pass-123")
    fleet.members.add(user)
    token = FleetToken.objects.create(fleet=fleet, user=user, description="bench")
    api = APIClient()
    api.credentials(HTTP_AUTHORIZATION=f"Token {token.plaintext}")
    small = {"format": "continuum.cluster/v1", "nodes": [{"name": f"node-{i:05d}", "cpu": 4} for i in range(4)]}
    cluster = api.post("/api/v1/clusters/import/", {"name": "bench", **small}, format="json").json()["id"]
    dag = {"format": "continuum.dag/v1", "name": "d", "tasks": [{"id": "a", "cost": {"cpu": 1}}], "edges": []}
    app = api.post("/api/v1/applications/", {"name": "d", "dag": dag}, format="json").json()["id"]
    assertion = api.post("/api/v1/assertions/", {"name": "a", "text": "G(x > 0)"}, format="json").json()["id"]
    ids = {"applications": app, "clusters": cluster, "assertions": assertion}

    schema = SchemaGenerator().get_schema(request=None, public=True)
    endpoints = []
    for path, operations in schema["paths"].items():
        for method in ("post", "put", "patch"):
            if method not in operations:
                continue
            resource = path.split("/")[3]
            if "{" in path and resource not in ids:
                continue  # an object this run does not make: the request would end at its 404
            concrete = path.replace("{id}", str(ids.get(resource, 0)))
            endpoints.append((method, concrete))

    documents = {
        "/api/v1/placements/run/": lambda size: placement_doc(cluster, lim, size),
        "/api/v1/clusters/import/": lambda size: cluster_doc(lim, size, "worst"),
        "/api/v1/applications/": lambda size: dag_doc(lim, size),
        "/api/v1/events/": lambda size: events_doc(cluster, size),
        "/api/v1/rt-reports/": lambda size: reports_doc(cluster, size),
    }
    rows = []
    for method, path in endpoints:
        if only and only not in path:
            continue
        # The endpoint's limit as the server applies it: probe with a body one byte too many of each size.
        limit = None
        for candidate in (lim.body_bytes, lim.upload_bytes + UPLOAD_FRAMING_BYTES):
            probe = api.generic(method.upper(), path, b" " * (candidate + 1), content_type="application/json")
            if probe.status_code == 413:
                limit = candidate
                break
        size = int((limit or lim.upload_bytes) * scale)
        shapes = generic_shapes(size, limit or lim.upload_bytes)
        if method == "post" and path in documents:
            shapes["document"] = (documents[path](size), "application/json")
        for shape, (body, content_type) in shapes.items():
            cpu, wall = time.process_time(), time.perf_counter()
            response = api.generic(method.upper(), path, body, content_type=content_type)
            wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
            print(f"{method.upper()} {path} {shape}: {len(body):,} B -> {response.status_code} in {wall:.2f} s",
                  file=sys.stderr, flush=True)  # fmt: skip
            rows.append({"endpoint": f"{method.upper()} {path}", "limit": limit, "shape": shape, "bytes": len(body),
                         "status": response.status_code, "wall_s": wall, "cpu_s": cpu,
                         "cpu_us_per_byte": cpu * 1e6 / max(1, len(body))})  # fmt: skip
    return {"rows": rows, "loadavg": loadavg(), "limits": {"body_bytes": lim.body_bytes,
                                                           "upload_bytes": lim.upload_bytes}}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--database-url", default="", help="PostgreSQL to use (created and dropped); default SQLite")
    parser.add_argument("--scale", type=float, default=1.0, help="fraction of each body limit to send")
    parser.add_argument("--only", default=None, help="endpoints whose path contains this")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="continuum-limits-") as var:
        os.environ["CONTINUUM_VAR_DIR"] = var
        os.environ["XDG_CONFIG_HOME"] = str(Path(var) / "config")
        for name in ("CONTINUUM_JOBS_EAGER", "CELERY_BROKER_URL", "CONTINUUM_CACHE_URL"):
            os.environ.pop(name, None)  # jobs queued to files nothing reads; counters in memory
        os.environ["CONTINUUM_THROTTLE_TOKEN"] = "1000000/min"
        if args.database_url:
            os.environ["DATABASE_URL"] = recreate_database(args.database_url)
        else:
            os.environ.pop("DATABASE_URL", None)
        start = loadavg()
        try:
            result = run(args.scale, args.only)
        finally:
            if args.database_url:
                from django.db import connections

                connections.close_all()
                drop_database(args.database_url)
    result["loadavg_before"] = start
    if args.json:
        print(json.dumps(result, indent=1))
        return
    rows = result["rows"]
    worst: dict[str, dict] = {}
    for row in rows:
        if row["endpoint"] not in worst or row["cpu_s"] > worst[row["endpoint"]]["cpu_s"]:
            worst[row["endpoint"]] = row
    print(f"database: {'PostgreSQL' if args.database_url else 'SQLite'}; scale {args.scale}; limits {result['limits']}")
    print(table(
        ["endpoint", "limit B", "worst shape", "bytes", "status", "wall s", "CPU s", "CPU us/B"],
        [[r["endpoint"], r["limit"] or "-", r["shape"], r["bytes"], r["status"], r["wall_s"], r["cpu_s"],
          r["cpu_us_per_byte"]] for r in worst.values()],
    ))  # fmt: skip
    top = max(rows, key=lambda r: r["wall_s"])
    servers = [r for r in rows if r["status"] >= 500]
    print(
        f"worst request: {top['endpoint']} {top['shape']} {top['bytes']:,} B -> {top['status']} in "
        f"{top['wall_s']:.2f} s wall, {top['cpu_s']:.2f} s CPU; {len(rows)} requests, {len(servers)} answered 5xx"
    )
    over = [r for r in rows if r["shape"] == "over" and r["status"] != 413]
    print(f"bodies over their limit not refused with 413: {len(over)}")
    print(f"load average before: {result['loadavg_before']}, after: {result['loadavg']}")


if __name__ == "__main__":
    main()
