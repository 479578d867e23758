"""The retry policy against a loopback server that answers as a busy or broken server does: a request the
server did not act on is sent again, a request whose effect is unknown is not (unless it is idempotent)."""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import pytest

from continuum.fleet import ApiError, Fleet, MissReport


@pytest.fixture
def scripted() -> Iterator[tuple[str, list, list]]:
    """A server answering each request with the next (status, headers, body) of ``answers``; ``seen`` records the
    requests' paths and JSON bodies."""
    answers: list[tuple[int, dict, dict]] = []
    seen: list[tuple[str, dict]] = []

    class Handler(BaseHTTPRequestHandler):
        def do_POST(self) -> None:
            body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
            seen.append((self.path, body))
            status, headers, payload = answers.pop(0)
            data = json.dumps(payload).encode()
            self.send_response(status)
            for k, v in {**headers, "Content-Type": "application/json", "Content-Length": str(len(data))}.items():
                self.send_header(k, v)
            self.end_headers()
            self.wfile.write(data)

        def log_message(self, *args) -> None:
            pass

    server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}", answers, seen
    finally:
        server.shutdown()
        server.server_close()


def test_a_busy_server_gets_the_same_reports_again(scripted):
    url, answers, seen = scripted
    answers += [(503, {"Retry-After": "0"}, {"detail": "busy"}), (502, {}, {"detail": "bad gateway"}),
                (201, {}, {"stored": 1, "duplicates": []})]  # fmt: skip
    with Fleet(url, "t0k3n", retries=3, backoff=0.01) as fleet:
        answer = fleet.report_misses([MissReport("node0", "slam", 1, 4)], cluster=7)
    assert answer == [{"stored": 1, "duplicates": []}]
    assert [p for p, _ in seen] == ["/api/v1/rt-reports/"] * 3
    ids = {b["reports"][0]["id"] for _, b in seen}
    assert len(ids) == 1  # the same idempotency key each time: the server stores the report once
    assert seen[0][1]["cluster"] == 7 and seen[0][1]["reports"][0]["missedDeadlinesTotal"] == 4


def test_events_are_not_sent_twice_when_their_fate_is_unknown(scripted):
    url, answers, seen = scripted
    answers += [(429, {"Retry-After": "0"}, {"detail": "slow down"}), (502, {}, {"detail": "bad gateway"})]
    with Fleet(url, "t0k3n", retries=3, backoff=0.01) as fleet, pytest.raises(ApiError) as err:
        fleet.post_events(1, [["speed", 1, 0]])
    assert len(seen) == 2  # 429: not taken, sent again; 502: maybe taken, not sent again
    assert err.value.status == 502 and str(err.value) == "events: HTTP 502: bad gateway"


def test_a_refused_request_is_not_retried(scripted):
    url, answers, seen = scripted
    answers += [(400, {}, {"reports": ["reports[0]: node 'x' is not a node of cluster 'edge'"]})]
    with Fleet(url, "t0k3n", retries=3, backoff=0.01) as fleet, pytest.raises(ApiError) as err:
        fleet.report_misses([MissReport("x", "slam", 1, 1)])
    assert len(seen) == 1
    assert str(err.value) == "report: HTTP 400: reports: reports[0]: node 'x' is not a node of cluster 'edge'"
