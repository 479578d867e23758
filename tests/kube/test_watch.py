"""The gateway's one watch loop (apps/kube/watch.py): list, watch from the list's resourceVersion, resume a
watch the server ended, start over after 410 Gone, back off after failures, give up after ``retries``.

A tiny plain-HTTP API on loopback answers the node list and the watch streams from a script, through the
real client: no database, no kube-apiserver.
"""

import json
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from urllib.parse import parse_qs, urlsplit

import pytest
from kubernetes import client

from apps.kube import gateway
from tests.kubeapi import free_port


def node(name: str, rv: str, ready: str = "True") -> dict:
    return {
        "metadata": {"name": name, "resourceVersion": rv},
        "status": {"conditions": [{"type": "Ready", "status": ready}]},
    }


class ScriptedAPI:
    """``GET /api/v1/nodes``: lists come from ``lists`` (``{"resourceVersion", "items"}``), watches from
    ``watches`` (a list of events per request). Records each request's query."""

    def __init__(self, lists: list[dict], watches: list[list[dict]]) -> None:
        self.lists, self.watches = list(lists), list(watches)
        self.requests: list[dict] = []
        fake = self

        class Handler(BaseHTTPRequestHandler):
            protocol_version = "HTTP/1.1"

            def do_GET(self):
                query = {k: v[0] for k, v in parse_qs(urlsplit(self.path).query).items()}
                fake.requests.append(query)
                if query.get("watch") == "true":
                    events = fake.watches.pop(0) if fake.watches else []
                    body = b"".join(json.dumps(e).encode() + b"\n" for e in events)
                else:
                    listing = fake.lists.pop(0)
                    body = json.dumps(
                        {"kind": "NodeList", "apiVersion": "v1", "metadata": {"resourceVersion": listing["rv"]},
                         "items": listing["items"]}
                    ).encode()  # fmt: skip
                self.send_response(200)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)

            def log_message(self, *args):
                pass

        self.server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.url = f"http://127.0.0.1:{self.server.server_address[1]}"
        threading.Thread(target=self.server.serve_forever, daemon=True).start()

    def connect(self) -> client.ApiClient:
        configuration = client.Configuration()
        configuration.host = self.url
        return client.ApiClient(configuration)

    def close(self) -> None:
        self.server.shutdown()
        self.server.server_close()


@pytest.fixture
def scripted():
    made = []

    def make(lists, watches):
        made.append(ScriptedAPI(lists, watches))
        return made[-1]

    yield make
    for fake in made:
        fake.close()


def test_list_then_watch_from_its_version_resume_and_relist_after_410(scripted):
    gone = {"type": "ERROR", "object": {"kind": "Status", "code": 410, "reason": "Expired", "message": "too old"}}
    fake = scripted(
        lists=[{"rv": "10", "items": [node("a", "9")]}, {"rv": "20", "items": [node("a", "19", "False")]}],
        watches=[
            [{"type": "MODIFIED", "object": node("a", "11", "False")}],  # then the server ends the watch
            [gone],  # the resumed watch's version expired: list again
            [{"type": "DELETED", "object": node("a", "21")}],
        ],
    )
    stop = threading.Event()
    listed, seen = [], []

    def on_event(event):
        seen.append((event["type"], gateway.name_of(event["raw_object"]), gateway.node_status(event["raw_object"])))
        if event["type"] == "DELETED":
            stop.set()

    stats = gateway.follow(
        fake.connect,
        gateway.watch_nodes(),
        on_event,
        on_list=lambda items: listed.append({gateway.name_of(n): gateway.node_status(n) for n in items}),
        stop=stop,
        timeout=30,
        retries=0,
    )
    assert listed == [{"a": "Ready"}, {"a": "NotReady"}]
    assert seen == [("MODIFIED", "a", "NotReady"), ("DELETED", "a", "Ready")]
    watches = [(q.get("resourceVersion")) for q in fake.requests if q.get("watch") == "true"]
    assert watches == ["10", "11", "20"]  # from the list, resumed from the last event, from the new list
    assert (stats.lists, stats.events, stats.reconnects) == (2, 2, 0)


def test_without_a_list_the_first_watch_starts_now_and_later_ones_resume(scripted):
    fake = scripted(
        lists=[],
        watches=[[{"type": "ADDED", "object": node("a", "5")}], [{"type": "MODIFIED", "object": node("a", "6")}]],
    )
    stop = threading.Event()
    seen = []

    def on_event(event):
        seen.append(event["type"])
        if len(seen) == 2:
            stop.set()

    stats = gateway.follow(fake.connect, gateway.watch_nodes(), on_event, stop=stop, timeout=30, retries=None)
    assert seen == ["ADDED", "MODIFIED"]
    assert [q.get("resourceVersion") for q in fake.requests] == [None, "5"]
    assert stats.lists == 0 and stats.events == 2


def test_failures_back_off_exponentially_then_give_up_naming_the_reason():
    def connect():
        configuration = client.Configuration()
        configuration.host = f"http://127.0.0.1:{free_port()}"  # nothing listens there
        configuration.retries = False
        return client.ApiClient(configuration)

    waits = []
    with pytest.raises(gateway.KubeError, match="node watch gave up after 3 reconnects: Kubernetes API unreachable"):
        gateway.follow(
            connect, gateway.watch_nodes(), lambda e: None, on_list=lambda items: None, timeout=60, retries=3,
            backoff=0.5, max_backoff=1.5, sleep=waits.append, what="node watch",
        )  # fmt: skip
    assert waits == [0.5, 1.0, 1.5]  # doubled each time, capped


def test_a_stop_ends_the_loop_and_closes_open_watches(scripted):
    fake = scripted(lists=[], watches=[])  # every watch ends at once, empty
    stop = threading.Event()
    watches = gateway.Watches()
    timer = threading.Timer(0.5, stop.set)
    timer.start()
    stats = gateway.follow(fake.connect, gateway.watch_nodes(), lambda e: None, stop=stop, watches=watches)
    timer.join()
    assert stats.events == 0 and len(fake.requests) >= 1
    watches.close_all()  # nothing left open: a no-op
