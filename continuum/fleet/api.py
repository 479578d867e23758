"""What robots and operators do with the API, on top of the generated client (:mod:`continuum.client`).

The generated functions build every request and decode the documented answers; this layer adds what they leave
to the caller: a token client, one exception for every refusal (with the server's field errors as one line),
retries where a retry cannot repeat a side effect, batching, and following a job to its end. No Django.

Where the schema under-describes an answer (``POST /events/`` answers 200/202, not the documented 201; a report
batch may answer 202 with a job), the JSON body is returned as it came.
"""

from __future__ import annotations

import io
import json
import random
import time
import uuid
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any

import httpx

from continuum.client import AuthenticatedClient
from continuum.client.api.applications import (
    applications_import_create,
    applications_schedule_create,
)
from continuum.client.api.events import events_create
from continuum.client.api.jobs import jobs_retrieve
from continuum.client.api.rosgraphs import rosgraphs_import_create
from continuum.client.api.rt_reports import rt_reports_create
from continuum.client.api.schedules import schedules_assignments_list, schedules_push_create
from continuum.client.models import (
    ApplicationImportRequest,
    EventBatchRequest,
    Job,
    JobDetail,
    ReportBatchRequest,
    RosGraphImportRequest,
    ScheduleRequestRequest,
)
from continuum.client.types import UNSET, File, Response

#: The server's limits per request (apps/verification/services.py MAX_EVENTS, apps/realtime/monitoring.py).
MAX_EVENTS = 10_000
MAX_REPORTS = 5_000
#: Answers after which the same request may be sent again: the server did not act on it.
RETRY_STATUSES = {429, 503}
#: Also retried for idempotent requests (reads, reports with ids): the answer was lost, not the work.
RETRY_STATUSES_IDEMPOTENT = RETRY_STATUSES | {502, 504}
DONE = ("succeeded", "failed", "cancelled")


class ApiError(Exception):
    """The server refused a request (or could not be reached); ``str()`` is one line naming the problem."""

    def __init__(self, status: int | None, body: Any, what: str = ""):
        self.status, self.body, self.what = status, body, what
        super().__init__(self.line())

    def line(self) -> str:
        where = f"{self.what}: " if self.what else ""
        if self.status is None:
            return f"{where}{self.body}"
        return f"{where}HTTP {self.status}: {_errors_line(self.body)}"


class JobFailed(Exception):
    def __init__(self, job: Job | JobDetail):
        self.job = job
        super().__init__(f"job {job.id} ({job.kind}) {job.state}: {job.error or job.message or 'no reason given'}")


def _errors_line(body: Any) -> str:
    """DRF's error body (``{"field": ["message"]}``, ``{"detail": ...}``) as one line."""
    if isinstance(body, Mapping):
        parts = []
        for key, value in body.items():
            msgs = value if isinstance(value, list) else [value]
            text = "; ".join(_errors_line(m) if isinstance(m, Mapping | list) else str(m) for m in msgs)
            parts.append(text if key in ("detail", "non_field_errors") else f"{key}: {text}")
        return " | ".join(parts)[:500]
    if isinstance(body, list):
        return "; ".join(_errors_line(b) for b in body)[:500]
    return " ".join(str(body).split())[:500]


def _body(resp: Response) -> Any:
    try:
        return json.loads(resp.content) if resp.content else None
    except ValueError:
        return resp.content.decode(errors="replace")


@dataclass
class MissReport:
    """One report of missed deadlines (Listing 3.37's Monitoring spec, Eq. 3.19's ``missAt``/``sentAt``)."""

    node: str
    container: str
    missed_period: int
    missed_total: int
    pod: str = ""
    miss_at: datetime | float | None = None
    sent_at: datetime | float | None = None
    #: Idempotency key: the server drops a report whose id it has stored (a batch sent again after a lost answer).
    report_id: str = field(default_factory=lambda: uuid.uuid4().hex)

    def to_spec(self) -> dict[str, Any]:
        spec: dict[str, Any] = {
            "node": self.node,
            "containerName": self.container,
            "missedDeadlinesPeriod": self.missed_period,
            "missedDeadlinesTotal": self.missed_total,
            "id": self.report_id,
            "sentAt": _rfc3339(self.sent_at if self.sent_at is not None else time.time()),
        }
        if self.pod:
            spec["pod"] = self.pod
        if self.miss_at is not None:
            spec["missAt"] = _rfc3339(self.miss_at)
        return spec


def _rfc3339(t: datetime | float) -> str:
    stamp = t if isinstance(t, datetime) else datetime.fromtimestamp(t, UTC)
    return stamp.isoformat(timespec="microseconds").replace("+00:00", "Z")


def chunks(items: Sequence[Any], size: int) -> Iterator[Sequence[Any]]:
    for start in range(0, len(items), size):
        yield items[start : start + size]


class Fleet:
    """A fleet token's view of one Continuum server.

    >>> fleet = Fleet("https://continuum.example", token)          # doctest: +SKIP
    >>> fleet.report_misses([MissReport("jetson1", "slam", 3, 17)])  # doctest: +SKIP
    """

    def __init__(
        self, server: str, token: str, *, timeout: float = 30.0, retries: int = 4, backoff: float = 0.5
    ) -> None:
        if not server.startswith(("http://", "https://")):
            raise ValueError(f"server {server!r} is not an http(s) URL")
        if not token or not token.isprintable() or " " in token:
            raise ValueError("token must be a fleet API token (printable, no spaces)")
        self.server = server.rstrip("/")
        self.client = AuthenticatedClient(
            base_url=self.server, token=token, prefix="Token", timeout=httpx.Timeout(timeout)
        )
        self.retries, self.backoff = retries, backoff

    def close(self) -> None:
        self.client.get_httpx_client().close()

    def __enter__(self) -> Fleet:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ---- one call ---------------------------------------------------------------------------------------
    def call(self, what: str, fn: Callable[..., Response], *args: Any, idempotent: bool = False, **kw: Any) -> Response:
        """``fn.sync_detailed``-like call with retries; ApiError unless the answer is 2xx.

        Retried: a connection never made (nothing was sent), 429/503 (the server did nothing; ``Retry-After``
        is honoured); for idempotent requests also timeouts and 502/504. Never retried: other 4xx (the request is
        wrong and would be again) and a non-idempotent request whose answer was lost (it may have been acted on).
        """
        retryable = RETRY_STATUSES_IDEMPOTENT if idempotent else RETRY_STATUSES
        for attempt in range(self.retries + 1):
            last = attempt == self.retries
            try:
                resp = fn(*args, client=self.client, **kw)
            except (httpx.ConnectError, httpx.ConnectTimeout) as exc:
                if last:
                    raise ApiError(None, f"cannot reach {self.server}: {exc}", what) from exc
                self._sleep(attempt, None)
                continue
            except httpx.TransportError as exc:
                if last or not idempotent:
                    raise ApiError(None, f"{type(exc).__name__}: {exc}", what) from exc
                self._sleep(attempt, None)
                continue
            if 200 <= resp.status_code < 300:
                return resp
            if resp.status_code in retryable and not last:
                self._sleep(attempt, resp.headers.get("Retry-After"))
                continue
            raise ApiError(int(resp.status_code), _body(resp), what)
        raise AssertionError("unreachable")

    def _sleep(self, attempt: int, retry_after: str | None) -> None:
        try:
            wait = float(retry_after) if retry_after else 0.0
        except ValueError:
            wait = 0.0
        time.sleep(max(wait, min(30.0, self.backoff * 2**attempt) * (0.5 + random.random() / 2)))

    @staticmethod
    def parsed(resp: Response) -> Any:
        """The typed answer when the schema describes it, else the JSON body."""
        return resp.parsed if resp.parsed is not None else _body(resp)

    # ---- robots -----------------------------------------------------------------------------------------
    def report_misses(self, reports: Iterable[MissReport | Mapping[str, Any]], cluster: int | None = None) -> list[Any]:
        """Post missed-deadline reports (``POST /api/v1/rt-reports/``), in batches the server takes. Every report
        carries an id, so a batch is safely sent again. Returns each batch's answer (what the monitor did, or
        the ``rt_reports`` job when a worker reconciles it)."""
        specs = [r.to_spec() if isinstance(r, MissReport) else dict(r) for r in reports]
        if not specs:
            raise ValueError("no reports to send")
        answers = []
        for batch in chunks(specs, MAX_REPORTS):
            body = ReportBatchRequest.from_dict({"reports": list(batch)} | ({"cluster": cluster} if cluster else {}))
            resp = self.call("report", rt_reports_create.sync_detailed, body=body, idempotent=True)
            answers.append(_body(resp))
        return answers

    def post_events(
        self,
        cluster: int,
        events: Iterable[Sequence[Any] | Mapping[str, Any]],
        *,
        now: float | None = None,
        batch_size: int = 1000,
        on_batch: Callable[[int, dict], None] | None = None,
    ) -> list[dict]:
        """Post STL events (``[variable, value, timestamp_ms]``) to ``POST /api/v1/events/`` in batches of at most
        ``batch_size``; ``now`` goes with the last batch. ``on_batch(sent_so_far, answer)`` after each one."""
        if not 1 <= batch_size <= MAX_EVENTS:
            raise ValueError(f"batch_size must be 1..{MAX_EVENTS}")
        answers: list[dict] = []
        sent = 0
        batch: list[Any] = []

        def flush(final: bool) -> None:
            nonlocal sent
            payload: dict[str, Any] = {"cluster": cluster, "events": batch}
            if final and now is not None:
                payload["now"] = now
            # Not idempotent (events would be counted twice): retried only when the server did not take them.
            resp = self.call("events", events_create.sync_detailed, body=EventBatchRequest.from_dict(payload))
            answer = _body(resp)
            sent += len(batch)
            answers.append(answer)
            if on_batch:
                on_batch(sent, answer)

        for event in events:
            if len(batch) >= batch_size:  # sent once the next event exists, so that ``now`` rides the last batch
                flush(False)
                batch = []
            batch.append(list(event) if not isinstance(event, Mapping) else dict(event))
        if not batch:
            raise ValueError("no events to send")
        flush(True)
        return answers

    def upload_rosgraph(
        self,
        document: bytes | Mapping[str, Any],
        filename: str = "graph.json",
        *,
        name: str | None = None,
        fmt: str | None = None,
        description: str = "",
    ):
        """Upload a ROS graph (``continuum.rosgraph/v1`` dict, or any file the server reads) -> the stored graph."""
        data = json.dumps(document).encode() if isinstance(document, Mapping) else document
        body = RosGraphImportRequest(
            file=File(payload=io.BytesIO(data), file_name=filename, mime_type="application/octet-stream"),
            name=name if name else UNSET,
            description=description,
        )
        if fmt:
            body.format_ = fmt  # type: ignore[assignment]  # the server names the bad one
        return self.parsed(self.call("upload ROS graph", rosgraphs_import_create.sync_detailed, body=body))

    # ---- operators ----------------------------------------------------------------------------------------
    def upload_application(self, data: bytes, filename: str, *, name: str | None = None, fmt: str | None = None):
        """Upload a DAG file (continuum JSON, WfFormat, DAX, STG, the simulator's CSV) -> the application."""
        body = ApplicationImportRequest(
            file=File(payload=io.BytesIO(data), file_name=filename, mime_type="application/octet-stream"),
            name=name if name else UNSET,
        )
        if fmt:
            body.format_ = fmt  # type: ignore[assignment]
        return self.parsed(self.call("upload application", applications_import_create.sync_detailed, body=body))

    def schedule(self, application: int, **request: Any) -> Job:
        """Start a scheduling job (``algorithm``, ``cluster`` or ``platform``, ``frames``, ``fps``...)."""
        try:
            body = ScheduleRequestRequest.from_dict(request)
        except (TypeError, KeyError, ValueError) as exc:  # e.g. an unknown algorithm
            raise ValueError(f"schedule request: {exc}") from None
        return self.parsed(self.call("schedule", applications_schedule_create.sync_detailed, application, body=body))

    def push(self, schedule: int) -> Job:
        """Start the job that binds a schedule's pods in its cluster's Kubernetes API."""
        return self.parsed(self.call("push", schedules_push_create.sync_detailed, schedule))

    def assignments(self, schedule: int, page: int = 1000, **filters: Any) -> Iterator[Any]:
        """Every assignment of a schedule, in start order, read page by page from
        ``/schedules/{id}/assignments/`` (the schedule's own detail inlines at most 1,000); ``filters`` are that
        endpoint's (``task``, ``processor``, ``frame``, ``placement``)."""
        offset = 0
        while True:
            resp = self.call(
                "assignments",
                schedules_assignments_list.sync_detailed,
                schedule,
                limit=page,
                offset=offset,
                idempotent=True,
                **filters,
            )
            batch = self.parsed(resp)
            yield from batch.results
            offset += len(batch.results)
            if not batch.results or not batch.next_:
                return

    def job(self, job_id: uuid.UUID | str) -> Job | JobDetail:
        jid = job_id if isinstance(job_id, uuid.UUID) else uuid.UUID(str(job_id))
        return self.parsed(self.call("job", jobs_retrieve.sync_detailed, jid, idempotent=True))

    def wait(
        self,
        job: Job | JobDetail | uuid.UUID | str,
        *,
        poll: float = 0.5,
        timeout: float | None = None,
        on_progress: Callable[[Job], None] | None = None,
        raise_on_failure: bool = True,
    ) -> Job | JobDetail:
        """Follow a job until it succeeds, fails or is cancelled, calling ``on_progress(job)`` whenever its state,
        progress or message changes. Raises JobFailed (or returns the failed or cancelled job), TimeoutError after
        ``timeout`` seconds."""
        current = job if isinstance(job, Job | JobDetail) else self.job(job)
        deadline = None if timeout is None else time.monotonic() + timeout
        seen = None
        while True:
            key = (current.state, current.progress, current.message)
            if key != seen and on_progress:
                on_progress(current)
            seen = key
            if current.state in DONE:
                break
            if deadline is not None and time.monotonic() >= deadline:
                raise TimeoutError(f"job {current.id} still {current.state} after {timeout} s")
            time.sleep(poll)
            current = self.job(current.id)
        if current.state in ("failed", "cancelled") and raise_on_failure:
            raise JobFailed(current)
        return current
