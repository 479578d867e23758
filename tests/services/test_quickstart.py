"""`scripts/start` as users run it: a real gunicorn on the embedded SQLite database, in a private var dir."""

import os
import sqlite3
import stat

import pytest

from benchmarks.quickstart_load import ROOT, QuickStart, free_port, measure, parse_args, request

pytestmark = pytest.mark.services


@pytest.fixture(scope="module")
def quickstart(tmp_path_factory):
    var = tmp_path_factory.mktemp("quickstart") / "var"
    server = QuickStart(ROOT, var, free_port())
    yield server, var
    server.stop()


def mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


def test_serves_like_production_and_keeps_var_private(quickstart):
    server, var = quickstart
    assert server.server == "gunicorn"
    status, page = request(server.port, "GET", "/login/")
    assert status == 200 and "password" in page
    status, page = request(server.port, "GET", "/no-such-page/")
    # DEBUG is off: no URLconf listing (the styled 404 names the address it could not find, escaped)
    assert status == 404 and "URLconf" not in page and "Traceback" not in page
    # Static files with DEBUG off: the compressed, content-hashed copies collected at start.
    status, page = request(server.port, "GET", "/admin/login/")
    assert status == 200
    css = next(w.split('"')[0] for w in page.split('href="')[1:] if w.startswith("/static/admin/css/base."))
    assert css != "/static/admin/css/base.css"
    assert request(server.port, "GET", css)[0] == 200
    plotly = next((var / "staticfiles" / "vendor").glob("plotly.min.*.js"))
    assert request(server.port, "GET", f"/static/vendor/{plotly.name}")[0] == 200
    # The database, the secret key and the demo credentials are the owner's only.
    assert mode(var) == 0o700
    for name in ("continuum.sqlite3", "secret_key", "demo-credentials.txt"):
        assert mode(var / name) & 0o077 == 0, name
    with sqlite3.connect(var / "continuum.sqlite3") as db:
        assert db.execute("PRAGMA journal_mode").fetchone()[0] == "wal"


def test_sixteen_robots_posting_reports_at_once_lose_none(quickstart):
    server, _ = quickstart
    args = parse_args(["--robots", "16", "--requests", "20", "--batch", "1", "--violation-every", "5"])
    args.duration = float("inf")  # every batch is posted: the test is about answers, not speed
    result = measure(server, args)
    assert result["errors"] == 0, (result["answers"], result["error_examples"])
    assert result["reports_sent"] == 16 * 20
    assert result["reports_acknowledged"] == result["reports_stored"] == 16 * 20
    assert result["reports_lost"] == 0
