"""The quick start under load: robots posting RT-Kube missed-deadline reports to `scripts/start`'s server.

Runs the real quick start (`<root>/scripts/start`: migrate, demo data, the server it serves with) in a
throw-away var directory on a free loopback port, with the embedded SQLite database and its file broker. Then,
over the API with the demo fleet's token: one RealTime object per robot on the demo cluster, and ROBOTS
threads that each post REQUESTS batches of BATCH reports to /api/v1/rt-reports/ as fast as answers come
(every VIOLATION_EVERY-th batch of a robot crosses the threshold, so the monitor's reconcile writes too).

Printed: what the server is (gunicorn or runserver, DEBUG or not: a 404 page listing the URLconf), requests
and their answers by HTTP status, reports sent / acknowledged / stored / lost (acknowledged but not
stored), throughput and latency. `--root` runs another checkout's quick start (e.g. the main branch
exported with `git archive`) for a before/after comparison; it needs a `.venv` with the requirements.

    python benchmarks/quickstart_load.py [--robots 16 --requests 40 --batch 5 --duration 120] [--json]
"""

from __future__ import annotations

import argparse
import html
import http.client
import json
import os
import re
import signal
import socket
import statistics
import subprocess
import tempfile
import threading
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TOKEN_MARK = "fleet token for the API: "


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--robots", type=int, default=16, help="concurrent robots (threads)")
    p.add_argument("--requests", type=int, default=40, help="batches each robot posts")
    p.add_argument("--batch", type=int, default=5, help="reports per batch")
    p.add_argument("--violation-every", type=int, default=10, help="every n-th batch of a robot is a violation")
    p.add_argument("--duration", type=float, default=120, help="seconds at most; robots stop posting then")
    p.add_argument("--root", type=Path, default=ROOT, help="checkout whose scripts/start is run")
    p.add_argument("--json", action="store_true", help="print one JSON object instead of the report")
    return p.parse_args(argv)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class QuickStart:
    """`scripts/start` of a checkout, in its own var directory and process group."""

    def __init__(self, root: Path, var: Path, port: int, startup_s: float = 300) -> None:
        self.port, self.log_path = port, var.parent / "server.log"
        env = {k: v for k, v in os.environ.items() if k not in {"DATABASE_URL", "CELERY_BROKER_URL", "DEBUG",
                                                                 "DJANGO_SETTINGS_MODULE", "SECRET_KEY",
                                                                 "CONTINUUM_JOBS_EAGER"}}  # fmt: skip
        env.update(CONTINUUM_VAR_DIR=str(var), PORT=str(port), LOG_LEVEL="WARNING")
        self.proc = subprocess.Popen(
            [str(root / "scripts" / "start")],
            cwd=root,
            env=env,
            stdout=self.log_path.open("w"),
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
        deadline = time.monotonic() + startup_s
        while True:
            if self.proc.poll() is not None:
                raise RuntimeError(f"scripts/start exited {self.proc.returncode}:\n{self.log()[-3000:]}")
            if TOKEN_MARK in self.log() and self._answers():
                break
            if time.monotonic() > deadline:
                self.stop()
                raise RuntimeError(f"scripts/start did not serve within {startup_s:g} s:\n{self.log()[-3000:]}")
            time.sleep(0.3)
        self.token = self.log().split(TOKEN_MARK, 1)[1].split(")", 1)[0].strip()

    def log(self) -> str:
        return self.log_path.read_text(errors="replace")

    def _answers(self) -> bool:
        try:
            status, _ = request(self.port, "GET", "/login/", timeout=5)
        except OSError:
            return False
        return status == 200

    @property
    def server(self) -> str:
        text = self.log()
        return "gunicorn" if "Starting gunicorn" in text else "runserver" if "development server" in text else "?"

    def stop(self) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGTERM)
            try:
                self.proc.wait(30)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait(10)


def request(port: int, method: str, path: str, body=None, token: str = "", timeout: float = 60,
            conn: http.client.HTTPConnection | None = None) -> tuple[int, object]:  # fmt: skip
    """(status, parsed JSON or text) of one request; a connection given is reused (keep-alive)."""
    own = conn is None
    conn = conn or http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    headers = {"Content-Type": "application/json"}
    if token:
        headers["Authorization"] = f"Token {token}"
    try:
        conn.request(method, path, body=None if body is None else json.dumps(body), headers=headers)
        resp = conn.getresponse()
        raw = resp.read().decode(errors="replace")
    finally:
        if own:
            conn.close()
    try:
        return resp.status, json.loads(raw)
    except ValueError:
        return resp.status, raw


def seed(qs: QuickStart, robots: int) -> tuple[int, list[dict]]:
    """The demo cluster and one RealTime object (a B container) per robot, over the API."""
    status, clusters = request(qs.port, "GET", "/api/v1/clusters/", token=qs.token)
    assert status == 200 and clusters["results"], (status, clusters)
    cluster = clusters["results"][0]["id"]
    status, nodes = request(qs.port, "GET", f"/api/v1/nodes/?cluster={cluster}&limit=500", token=qs.token)
    assert status == 200 and nodes["results"], (status, nodes)
    names = [n["name"] for n in nodes["results"]]
    containers = []
    for i in range(robots):
        node = names[i % len(names)]
        body = {"cluster": cluster, "name": f"robot-{i}-ctl", "criticality": "B", "period": 100, "deadline": 100,
                "wcets": [{"node": node, "wcet": 10}]}  # fmt: skip
        status, out = request(qs.port, "POST", "/api/v1/realtimes/", body, token=qs.token)
        assert status == 201, (status, out)
        containers.append({"node": node, "container": body["name"]})
    return cluster, containers


def robot(port: int, token: str, cluster: int, me: dict, args, stop_at: float, out: dict) -> None:
    """One robot: REQUESTS batches, one after the other, on a kept-alive connection."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    total = 0
    for k in range(args.requests):
        if time.monotonic() >= stop_at:
            break
        reports = []
        for j in range(args.batch):
            missed = 15 if (j == 0 and (k + 1) % args.violation_every == 0) else (k + j) % 3
            total += missed
            reports.append({"node": me["node"], "containerName": me["container"], "missedDeadlinesPeriod": missed,
                            "missedDeadlinesTotal": total, "sentAt": time.time()})  # fmt: skip
        sent = time.monotonic()
        try:
            status, body = request(port, "POST", "/api/v1/rt-reports/", {"cluster": cluster, "reports": reports},
                                   token=token, conn=conn)  # fmt: skip
        except (OSError, http.client.HTTPException) as exc:
            status, body = 0, str(exc)
            conn.close()
            conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
        out["latency"].append(time.monotonic() - sent)
        out["status"][status] += 1
        out["sent"] += len(reports)
        if status == 201 and isinstance(body, dict):
            out["acknowledged"] += body.get("accepted", 0)
        elif status not in out["examples"]:
            out["examples"][status] = error_text(body)
    conn.close()


def error_text(body) -> str:
    """The gist of an error answer: JSON as it is, Django's debug page by its exception line."""
    text = str(body)
    hit = re.search(r'<pre class="exception_value">(.*?)</pre>', text, re.S)
    if hit:
        return html.unescape(hit.group(1)).strip()[:300]
    hit = re.search(r"<title>(.*?)</title>", text, re.S)
    return html.unescape(hit.group(1)).strip()[:300] if hit else text[:300]


def run(args) -> dict:
    with tempfile.TemporaryDirectory(prefix="continuum-qs-") as tmp:
        qs = QuickStart(args.root.resolve(), Path(tmp) / "var", free_port())
        try:
            return {"root": str(args.root), **measure(qs, args)}
        finally:
            qs.stop()


def measure(qs: QuickStart, args) -> dict:
    """The robots' load on a running quick start, and what the server says it stored."""
    port = qs.port
    status, page = request(port, "GET", "/no-such-page/")
    debug = status == 404 and "URLconf" in str(page)
    cluster, containers = seed(qs, args.robots)
    # One tally per robot (no shared counters between threads), summed afterwards.
    shared = [{"status": Counter(), "sent": 0, "acknowledged": 0, "latency": [], "examples": {}}
              for _ in containers]  # fmt: skip
    began = time.monotonic()
    threads = [
        threading.Thread(target=robot, args=(port, qs.token, cluster, c, args, began + args.duration, s))
        for c, s in zip(containers, shared, strict=True)
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    elapsed = time.monotonic() - began
    out = {"status": Counter(), "sent": 0, "acknowledged": 0, "latency": [], "examples": {}}
    for s in shared:
        out["status"].update(s["status"])
        out["sent"] += s["sent"]
        out["acknowledged"] += s["acknowledged"]
        out["latency"] += s["latency"]
        for k, v in s["examples"].items():
            out["examples"].setdefault(k, v)
    status, page = request(port, "GET", f"/api/v1/rt-reports/?cluster={cluster}&limit=1", token=qs.token)
    stored = page["count"] if status == 200 else None
    server = qs.server
    lat = sorted(1000 * x for x in out["latency"])
    latency = None
    if lat:
        latency = {"p50": round(statistics.median(lat), 1), "p99": round(lat[int(0.99 * (len(lat) - 1))], 1),
                   "max": round(lat[-1], 1)}  # fmt: skip
    requests = sum(out["status"].values())
    return {
        "server": server,
        "debug_404_lists_urlconf": debug,
        "robots": args.robots,
        "requests": requests,
        "answers": {str(k): v for k, v in sorted(out["status"].items())},
        "errors": requests - out["status"][201],
        "error_examples": {str(k): v for k, v in out["examples"].items()},
        "reports_sent": out["sent"],
        "reports_acknowledged": out["acknowledged"],
        "reports_stored": stored,
        "reports_lost": None if stored is None else out["acknowledged"] - stored,
        "reports_rejected": out["sent"] - out["acknowledged"],
        "seconds": round(elapsed, 2),
        "reports_per_s": round(out["acknowledged"] / elapsed, 1) if elapsed else None,
        "latency_ms": latency,
    }


def main() -> None:
    args = parse_args()
    r = run(args)
    if args.json:
        print(json.dumps(r))
        return
    print(f"\nquick start ({r['root']}) under load: {r['server']}, SQLite, "
          f"DEBUG {'on (404 pages list the URLconf)' if r['debug_404_lists_urlconf'] else 'off'}")  # fmt: skip
    print(f"  {r['robots']} robots x up to {args.requests} batches of {args.batch} reports, "
          f"{r['seconds']} s")  # fmt: skip
    print(f"  requests {r['requests']}, errors {r['errors']} ({100 * r['errors'] / max(1, r['requests']):.0f} %); "
          "answers by status: " + ", ".join(f"{k}: {v}" for k, v in r["answers"].items()))  # fmt: skip
    for status, example in r["error_examples"].items():
        print(f"    e.g. {status}: {example[:160]!r}")
    print(f"  reports sent {r['reports_sent']}, acknowledged {r['reports_acknowledged']}, stored "
          f"{r['reports_stored']}, lost (acknowledged, not stored) {r['reports_lost']}, rejected "
          f"{r['reports_rejected']}")  # fmt: skip
    if r["latency_ms"]:
        lat = r["latency_ms"]
        print(f"  {r['reports_per_s']} reports/s acknowledged; request latency ms: p50 {lat['p50']}  p99 {lat['p99']}"
              f"  max {lat['max']}")  # fmt: skip


if __name__ == "__main__":
    main()
