"""Rate limits: per token (or user), per address for anonymous callers and bad keys, and per scope.

The throttles count in the Django cache (Redis in production, see ``CACHES`` in the settings). The rates are
settings (``REST_FRAMEWORK["DEFAULT_THROTTLE_RATES"]`` and ``CONTINUUM_THROTTLE_BAD_TOKENS``), read on every
request so that they can change without a restart of the class (and in tests with ``override_settings``).
A view takes its own budget with ``throttle_scope`` (e.g. "reports" for the robots' report endpoints); the
general per-token budget then leaves it alone.
"""

from __future__ import annotations

import logging
import time

from django.conf import settings
from django.core.cache import cache
from rest_framework import exceptions, throttling
from rest_framework.settings import api_settings

from .clientaddr import client_address
from .models import FleetToken

log = logging.getLogger(__name__)

PERIODS = {"s": 1, "m": 60, "h": 3600, "d": 86400}


def parse_rate(rate: str | None) -> tuple[int, int] | None:
    """``"100/min"`` -> (100, 60); None or "" -> no limit."""
    if not rate:
        return None
    num, period = rate.split("/")
    return int(num), PERIODS[period.strip()[0]]


class WindowThrottle(throttling.BaseThrottle):
    """A counter per caller (``cache.incr``) for a window that opens with the caller's first request, not
    DRF's list of request times: that list is read and written whole on every request, which at thousands of
    requests a minute costs more than the request. The rate is read from the current settings on every
    request (also under override_settings)."""

    scope: str = ""

    def rate(self, view) -> tuple[int, int] | None:
        return parse_rate(api_settings.DEFAULT_THROTTLE_RATES.get(self.scope))

    def ident(self, request, view) -> str | None:
        raise NotImplementedError

    def allow_request(self, request, view) -> bool:
        rate = self.rate(view)
        ident = self.ident(request, view) if rate else None
        if ident is None:
            return True
        limit, period = rate
        self._wait = period  # at most: the window started with the caller's first request in it
        return count(f"throttle_{self.scope}_{ident}", period) <= limit

    def wait(self) -> float | None:
        return getattr(self, "_wait", None)


def count(key: str, timeout: int) -> int:
    """Add one to a counter that lives ``timeout`` seconds from its first use; the new value (0 when the cache
    cannot be reached: see :func:`cache_down`)."""
    try:
        if cache.add(key, 1, timeout=timeout):
            return 1
        try:
            return cache.incr(key)
        except ValueError:  # expired between add and incr
            cache.set(key, 1, timeout=timeout)
            return 1
    except Exception as exc:  # any failure of the cache's backend (redis, memcached, ...)
        cache_down(exc)
        return 0


def forget(key: str) -> None:
    """Delete a counter (a successful login clears its failures); nothing when the cache is down."""
    try:
        cache.delete(key)
    except Exception as exc:
        cache_down(exc)


def cached(key: str) -> int:
    """A counter's value, 0 when it is not set or the cache cannot be reached."""
    try:
        return int(cache.get(key, 0) or 0)
    except Exception as exc:
        cache_down(exc)
        return 0


_last_logged = 0.0


def cache_down(exc: BaseException) -> None:
    """The cache the limits count in is down: the limits fail open (every request is let through) so that the
    API keeps answering, and say so in the log, at most once every 10 s per process."""
    global _last_logged
    now = time.monotonic()
    if now - _last_logged >= 10:
        _last_logged = now
        log.warning("rate limits off: the cache is unreachable (%s: %s)", type(exc).__name__, exc)


def _caller(request) -> str | None:
    if isinstance(request.auth, FleetToken):
        return f"token-{request.auth.pk}"
    if request.user and request.user.is_authenticated:
        return f"user-{request.user.pk}"
    return None


class TokenRateThrottle(WindowThrottle):
    """Every authenticated request, counted per fleet token (or per user for sessions), scope "user"."""

    scope = "user"

    def ident(self, request, view) -> str | None:
        if getattr(view, "throttle_scope", None):
            return None  # the view has its own budget (ScopedTokenThrottle)
        return _caller(request)


class ScopedTokenThrottle(WindowThrottle):
    """A view's own budget (its ``throttle_scope``), counted per fleet token (or user, or address)."""

    def allow_request(self, request, view) -> bool:
        self.scope = getattr(view, "throttle_scope", None) or ""
        return not self.scope or super().allow_request(request, view)

    def ident(self, request, view) -> str | None:
        return _caller(request) or self.get_ident(request)

    def get_ident(self, request) -> str:
        return client_address(request)


class AnonymousRateThrottle(WindowThrottle):
    """Requests without credentials, counted per client address, scope "anon"."""

    scope = "anon"

    def ident(self, request, view) -> str | None:
        return None if request.user and request.user.is_authenticated else client_address(request)


# ---- bad token keys -------------------------------------------------------------------------------------------
def _bad_token_key(request) -> str:
    return f"throttle_bad_token_{client_address(request)}"


def check_bad_tokens(request) -> None:
    """429 for an address that sent too many unknown keys in the window: guessing keys gets nowhere."""
    limit = parse_rate(settings.CONTINUUM_THROTTLE_BAD_TOKENS)
    if request is None or limit is None:
        return
    if cached(_bad_token_key(request)) >= limit[0]:
        raise exceptions.Throttled(wait=limit[1], detail="too many invalid tokens from this address; retry later")


def record_bad_token(request) -> None:
    limit = parse_rate(settings.CONTINUUM_THROTTLE_BAD_TOKENS)
    if request is not None and limit is not None:
        count(_bad_token_key(request), limit[1])  # the window starts at the first failure
