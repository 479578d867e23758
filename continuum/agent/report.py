"""Reports of missed deadlines to Continuum's monitoring endpoint (``POST /api/v1/rt-reports/``), stdlib only.

Every ``interval`` seconds (the thesis' 1/f_c; 0.5 s by default) the counters become one report, Listing 3.37's
Monitoring spec: ``node``, ``containerName``, ``pod``, ``missedDeadlinesPeriod`` (overruns since the previous
report), ``missedDeadlinesTotal`` (since the command started), Eq. 3.19's ``missAt`` (the first overrun of the
report's period: when the miss that the report carries happened) and ``sentAt`` (when it left), plus ``id``
(a UUID, for the server to drop a batch it has already stored when an answer was lost and the batch is sent
again). A report is made only when there is something new: at the start (a 0/0 report: the container is
monitored), for each interval with overruns (the last one when the command ends), and the kernel's refusal.

Nothing is lost while the server cannot be reached: reports wait in an outbox, in order, and each attempt sends
all of them in one batch (the endpoint takes many) after an exponential back-off with jitter (``interval`` up
to ``max_backoff``). Past ``max_outbox`` waiting reports the two oldest are merged into one (periods summed,
the later total, the earlier missAt), so memory stays bounded and every count still arrives. A 4xx answer
other than 408/429 (a malformed report, a node the cluster does not have, a bad token) is not retried: the
counting goes on, and the error is reported by :meth:`Reporter.summary`.

A redirect is never followed (:func:`urlopen`): following it sent the fleet token to whatever host the
``Location`` named, and urllib turned the POST into a GET whose 200 counted the report as delivered. A 3xx
answer is a failure that is not retried, like a 4xx: the reports stay pending and the error says where the server
tried to send them.
"""

from __future__ import annotations

import json
import random
import threading
import time
import urllib.error
import urllib.request
import uuid
from collections import deque
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any

ENDPOINT = "/api/v1/rt-reports/"


class _NoRedirect(urllib.request.HTTPRedirectHandler):
    def redirect_request(self, req, fp, code, msg, headers, newurl):  # type: ignore[no-untyped-def,unused-ignore]
        return None  # urllib then raises HTTPError with the 3xx status: nothing is sent to the new location


_OPENER = urllib.request.build_opener(_NoRedirect)


def urlopen(request: urllib.request.Request, timeout: float) -> Any:
    """``urllib.request.urlopen`` that never follows a redirect (a 3xx raises ``HTTPError``)."""
    return _OPENER.open(request, timeout=timeout)


def http_problem(exc: urllib.error.HTTPError) -> str:
    """An HTTP error in words (a redirect names where it pointed, and that it was not followed)."""
    if 300 <= exc.code < 400:
        where = exc.headers.get("Location", "?") if exc.headers else "?"
        return (f"HTTP {exc.code}: the server redirected to {where[:200]!r}; redirects are refused (the token goes "
                "only to --server)")  # fmt: skip
    return f"HTTP {exc.code}: {exc.read()[:500].decode(errors='replace')}"


def rfc3339(t: float) -> str:
    return datetime.fromtimestamp(t, UTC).isoformat(timespec="microseconds").replace("+00:00", "Z")


@dataclass
class Target:
    """Where and as whom reports go, and what they name."""

    server: str
    token: str
    node: str
    container: str
    pod: str = ""
    cluster: int | None = None
    timeout: float = 5.0

    @property
    def url(self) -> str:
        return self.server.rstrip("/") + ENDPOINT


@dataclass
class _Report:
    id: str
    missed_period: int
    missed_total: int
    miss_at: float | None
    extra: dict[str, Any] = field(default_factory=dict)
    startup: int = 0  # overruns during the command's warm-up in this report's period (not missed deadlines)

    def spec(self, target: Target, sent_at: float) -> dict[str, Any]:
        doc: dict[str, Any] = {
            "id": self.id,
            "node": target.node,
            "containerName": target.container,
            "missedDeadlinesPeriod": self.missed_period,
            "missedDeadlinesTotal": self.missed_total,
            "sentAt": rfc3339(sent_at),
        }
        if target.pod:
            doc["pod"] = target.pod
        if self.miss_at is not None:
            doc["missAt"] = rfc3339(self.miss_at)
        if self.startup:
            doc["startupOverruns"] = self.startup
        return doc | self.extra


class Reporter:
    """Counts overruns (from any thread) and delivers them from its own thread; see the module docstring."""

    def __init__(
        self,
        target: Target | None,
        interval: float = 0.5,
        max_backoff: float = 10.0,
        max_outbox: int = 10_000,
        max_batch: int = 1000,
    ):
        self.target = target
        self.interval = interval
        self.max_backoff = max(max_backoff, interval)
        self.max_outbox = max(2, max_outbox)
        self.max_batch = max(1, max_batch)
        self._lock = threading.Lock()
        self._wake = threading.Condition(self._lock)
        self.overruns = 0  # SIGXCPU counted
        self.total = 0  # missedDeadlinesTotal: the overruns, plus the job a kernel refusal could not run
        self.startup_overruns = 0  # overruns before the command was ready: counted apart, never missed deadlines
        self._startup_period = 0
        self._period = 0
        self._first_miss: float | None = None
        self._outbox: deque[_Report] = deque()
        self._closing = False
        self._thread: threading.Thread | None = None
        # what reached the server
        self.acknowledged = 0  # overruns (missedDeadlinesPeriod) in acknowledged reports
        self.startup_acknowledged = 0
        self.reports_acknowledged = 0
        self.rejection_acknowledged = False
        self.server_violations = 0
        self.failures = 0
        self.last_error: str | None = None
        self.fatal: str | None = None
        self._attempt = 0
        self._next_try = 0.0
        self._flush_until = 0.0

    # -- counting (the tracer's thread) --
    def overrun(self, at: float) -> None:
        with self._lock:
            self.overruns += 1
            self.total += 1
            self._period += 1
            if self._first_miss is None:
                self._first_miss = at

    def startup_overrun(self, at: float) -> None:
        """An overrun during the command's warm-up (interpreter start, loading): reported as ``startupOverruns``,
        not in ``missedDeadlines*``, so it never counts towards an eviction."""
        with self._lock:
            self.startup_overruns += 1
            self._startup_period += 1

    # -- the reports --
    def _snapshot(self, extra: dict[str, Any] | None = None, force: bool = False) -> None:
        """Turn the counters into a report (lock held)."""
        if not self._period and not self._startup_period and not force:
            return
        self._outbox.append(_Report(str(uuid.uuid4()), self._period, self.total, self._first_miss, extra or {},
                                    self._startup_period))  # fmt: skip
        self._period, self._first_miss, self._startup_period = 0, None, 0
        while len(self._outbox) > self.max_outbox:
            a, b = self._outbox.popleft(), self._outbox.popleft()
            merged = _Report(b.id, a.missed_period + b.missed_period, b.missed_total,
                             a.miss_at if a.miss_at is not None else b.miss_at, a.extra | b.extra,
                             a.startup + b.startup)  # fmt: skip
            self._outbox.appendleft(merged)

    def kernel_rejected(self, reason: str) -> None:
        """The kernel refused the deadline task: one report of the job that could not run (its deadline is
        missed: a rejected task misses every deadline, Table 4.31), marked ``kernelRejected`` with the reason."""
        with self._lock:
            self.total += 1
            self._period += 1
            self._first_miss = time.time()
            self._snapshot({"kernelRejected": True, "reason": reason})

    def start(self) -> None:
        """The 0/0 report that says the container is monitored, then the reporting thread."""
        with self._lock:
            if not self._outbox:
                self._snapshot(force=True)
        if self.target is not None:
            self._thread = threading.Thread(target=self._run, name="continuum-agent-reporter", daemon=True)
            self._thread.start()

    def close(self, flush_timeout: float = 10.0) -> None:
        """The last overruns' report, then up to ``flush_timeout`` seconds (retrying) to deliver what waits."""
        with self._lock:
            self._snapshot()
            self._closing = True
            self._flush_until = time.monotonic() + flush_timeout
            self._next_try = 0.0
            self._wake.notify_all()
        if self._thread is not None:
            self._thread.join(flush_timeout + (self.target.timeout if self.target else 0) + 1)

    @property
    def pending(self) -> int:
        with self._lock:
            return sum(r.missed_period for r in self._outbox if not r.extra.get("kernelRejected")) + self._period

    def _run(self) -> None:
        next_tick = time.monotonic() + self.interval
        while True:
            with self._lock:
                now = time.monotonic()
                if now >= next_tick:
                    self._snapshot()
                    next_tick = now + self.interval
                if self._closing and (not self._outbox or self.fatal or now >= self._flush_until):
                    return
                if not self._outbox or self.fatal or now < self._next_try:
                    wake = next_tick
                    if self._outbox and not self.fatal:
                        wake = min(wake, self._next_try)
                    if self._closing:
                        wake = min(wake, self._flush_until)
                    self._wake.wait(max(0.0, wake - now))
                    continue
                batch = list(self._outbox)[: self.max_batch]
            ok = self._send(batch)  # outside the lock: the tracer keeps counting meanwhile
            with self._lock:
                if ok:
                    for _ in batch:
                        self._outbox.popleft()
                    self._attempt = 0
                    self._next_try = 0.0
                else:
                    self._attempt += 1
                    delay = min(self.max_backoff, self.interval * 2 ** (self._attempt - 1))
                    self._next_try = time.monotonic() + delay * random.uniform(0.5, 1.0)

    def _send(self, batch: list[_Report]) -> bool:
        assert self.target is not None
        sent = time.time()
        body: dict[str, Any] = {"reports": [r.spec(self.target, sent) for r in batch]}
        if self.target.cluster is not None:
            body["cluster"] = self.target.cluster
        request = urllib.request.Request(
            self.target.url,
            data=json.dumps(body).encode(),
            method="POST",
            headers={"Content-Type": "application/json", "Authorization": f"Token {self.target.token}"},
        )
        try:
            with urlopen(request, timeout=self.target.timeout) as response:
                answer = json.loads(response.read() or b"{}")
        except urllib.error.HTTPError as exc:
            self.failures += 1
            self.last_error = http_problem(exc)
            if 300 <= exc.code < 500 and exc.code not in (408, 429):
                self.fatal = self.last_error
            return False
        except (OSError, ValueError) as exc:  # refused, reset, timed out, DNS, a non-JSON answer
            self.failures += 1
            self.last_error = f"{type(exc).__name__}: {exc}"
            return False
        self.acknowledged += sum(r.missed_period for r in batch if not r.extra.get("kernelRejected"))
        self.startup_acknowledged += sum(r.startup for r in batch)
        self.reports_acknowledged += len(batch)
        self.rejection_acknowledged |= any(r.extra.get("kernelRejected") for r in batch)
        if isinstance(answer, dict) and isinstance(answer.get("violations"), int):
            self.server_violations += answer["violations"]
        return True
