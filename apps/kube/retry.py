"""Retrying Kubernetes API calls on transient failures (issue 12, "Robust on a busy machine").

A loaded API server answers 504/503/429 or drops connections; a call that is safe to repeat is retried with
exponential backoff and full jitter until ``CONTINUUM_KUBE_RETRY_DEADLINE_S`` (total, per call) runs out, then
:class:`GaveUp` names the call and its last cause. A call is "idempotent" when repeating it cannot do harm:
reads, and creates whose 409 answer the caller checks (an existing pod or binding that matches counts as
done). A call that is not idempotent is only retried when the request surely never reached the server
(the connection could not be opened) or the server said it did not process it (429). Other 4xx never retry.
"""

from __future__ import annotations

import random
import ssl
import time
from collections.abc import Callable
from typing import TypeVar

import urllib3
from django.conf import settings
from kubernetes.client.exceptions import ApiException

T = TypeVar("T")

#: HTTP answers worth repeating: throttled, or the server (or a proxy in front of it) failed transiently.
TRANSIENT_STATUSES = frozenset({429, 500, 502, 503, 504})
#: Never wait longer than this between two attempts, whatever Retry-After says.
MAX_SLEEP_S = 10.0


class GaveUp(urllib3.exceptions.HTTPError):
    """A call still failed when its retry deadline ran out; ``last`` is the last failure. (A failure not worth
    repeating propagates unchanged instead.) An ``HTTPError`` so that every caller already handling "the API is
    unreachable" as ``(ApiException, urllib3.exceptions.HTTPError, OSError)`` handles this too."""

    def __init__(self, what: str, attempts: int, elapsed: float, last: BaseException, cause: str) -> None:
        self.what, self.attempts, self.elapsed, self.last = what, attempts, elapsed, last
        super().__init__(f"{what}: gave up after {attempts} attempts in {elapsed:.1f} s: {cause}")


def deadline_s() -> float:
    return max(0.0, settings.CONTINUUM_KUBE_RETRY_DEADLINE_S)


def base_s() -> float:
    return max(0.0, settings.CONTINUUM_KUBE_RETRY_BASE_S)


def _never_sent(exc: BaseException) -> bool:
    """The request cannot have reached the server: the TCP connection was never established."""
    if isinstance(exc, urllib3.exceptions.MaxRetryError) and exc.reason is not None:
        exc = exc.reason
    return isinstance(
        exc, (urllib3.exceptions.NewConnectionError, urllib3.exceptions.ConnectTimeoutError, ConnectionRefusedError)
    )


def _untrusted(exc: BaseException) -> bool:
    """The server's certificate was refused (wrong CA or name): repeating cannot help."""
    seen: set[int] = set()
    stack = [exc]
    while stack:
        current = stack.pop()
        if not isinstance(current, BaseException) or id(current) in seen:  # ApiException.reason is a str
            continue
        seen.add(id(current))
        if isinstance(current, ssl.SSLCertVerificationError):
            return True
        stack.extend([getattr(current, "reason", None), current.__cause__, current.__context__])
        stack.extend(a for a in getattr(current, "args", ()) if isinstance(a, BaseException))
    return False


def transient(exc: BaseException, idempotent: bool = True) -> bool:
    """Whether repeating the call may succeed (and is safe)."""
    if _untrusted(exc):
        return False
    if isinstance(exc, ApiException):
        if exc.status == 429:
            return True
        return idempotent and exc.status in TRANSIENT_STATUSES
    if isinstance(exc, (urllib3.exceptions.HTTPError, OSError)):
        return idempotent or _never_sent(exc)
    return False


def retry_after(exc: BaseException) -> float | None:
    """Seconds the server asked us to wait (``Retry-After`` in seconds; HTTP dates are ignored)."""
    headers = getattr(exc, "headers", None) if isinstance(exc, ApiException) else None
    if not headers:
        return None
    try:
        return max(0.0, float(headers.get("Retry-After")))
    except (TypeError, ValueError):
        return None


def call(
    fn: Callable[..., T],
    *args,
    what: str,
    idempotent: bool = True,
    describe: Callable[[BaseException], str] = str,
    **kwargs,
) -> T:
    """``fn(*args, **kwargs)``, repeated on transient failures until the retry deadline; then :class:`GaveUp`.

    A ``_request_timeout=(connect, read)`` keyword is shortened to the time left, so one hung attempt cannot
    overrun the deadline by a whole read timeout."""
    deadline = deadline_s()
    base = base_s()
    started = time.monotonic()
    timeout = kwargs.get("_request_timeout")
    attempt = 0
    while True:
        attempt += 1
        left = deadline - (time.monotonic() - started)
        if isinstance(timeout, tuple) and len(timeout) == 2:
            kwargs["_request_timeout"] = (min(timeout[0], max(left, 1.0)), min(timeout[1], max(left, 1.0)))
        try:
            return fn(*args, **kwargs)
        except Exception as exc:  # classified right below; anything else is re-raised
            if not transient(exc, idempotent):
                raise
            elapsed = time.monotonic() - started
            # Full jitter: many workers retrying the same busy server must not synchronise.
            sleep = random.uniform(0, min(MAX_SLEEP_S, base * 2 ** (attempt - 1)))
            asked = retry_after(exc)
            if asked is not None:
                sleep = min(MAX_SLEEP_S, max(sleep, asked))
            if elapsed + sleep >= deadline:
                raise GaveUp(what, attempt, elapsed, exc, describe(exc)) from exc
            time.sleep(sleep)
