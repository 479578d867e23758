"""Rate limits: per token (or user), per address for anonymous callers and bad keys, and per scope.

DRF's throttles count in the Django cache (Redis in production, see ``CACHES`` in the settings). The rates are
settings (``REST_FRAMEWORK["DEFAULT_THROTTLE_RATES"]`` and ``CONTINUUM_THROTTLE_BAD_TOKENS``), read on every
request so that they can change without a restart of the class (and in tests with ``override_settings``).
A view takes its own budget with ``throttle_scope`` (e.g. "reports" for the robots' report endpoints); the
general per-token budget then leaves it alone.
"""

from __future__ import annotations

from django.conf import settings
from django.core.cache import cache
from rest_framework import exceptions, throttling
from rest_framework.settings import api_settings

from .models import FleetToken

PERIODS = {"s": 1, "m": 60, "h": 3600, "d": 86400}


def parse_rate(rate: str | None) -> tuple[int, int] | None:
    """``"100/min"`` -> (100, 60); None or "" -> no limit."""
    if not rate:
        return None
    num, period = rate.split("/")
    return int(num), PERIODS[period.strip()[0]]


class _SettingsRates:
    """Read the rate from the current settings, not from the class attribute DRF binds at import."""

    def get_rate(self):
        return api_settings.DEFAULT_THROTTLE_RATES.get(self.scope)


def _ident(request) -> str | None:
    if isinstance(request.auth, FleetToken):
        return f"token-{request.auth.pk}"
    if request.user and request.user.is_authenticated:
        return f"user-{request.user.pk}"
    return None


class TokenRateThrottle(_SettingsRates, throttling.UserRateThrottle):
    """Every authenticated request, counted per fleet token (or per user for sessions), scope "user"."""

    def get_cache_key(self, request, view):
        if getattr(view, "throttle_scope", None):
            return None  # the view has its own budget (ScopedTokenThrottle)
        ident = _ident(request)
        return self.cache_format % {"scope": self.scope, "ident": ident} if ident else None


class ScopedTokenThrottle(_SettingsRates, throttling.ScopedRateThrottle):
    """A view's own budget (``throttle_scope``), counted per fleet token (or user, or address)."""

    def get_cache_key(self, request, view):
        ident = _ident(request) or self.get_ident(request)
        return self.cache_format % {"scope": self.scope, "ident": ident}


class AnonymousRateThrottle(_SettingsRates, throttling.AnonRateThrottle):
    """Requests without credentials, counted per client address, scope "anon"."""


# ---- bad token keys -------------------------------------------------------------------------------------------
def _bad_token_key(request) -> str:
    return f"throttle_bad_token_{throttling.BaseThrottle().get_ident(request)}"


def check_bad_tokens(request) -> None:
    """429 for an address that sent too many unknown keys in the window: guessing keys gets nowhere."""
    limit = parse_rate(settings.CONTINUUM_THROTTLE_BAD_TOKENS)
    if request is None or limit is None:
        return
    if cache.get(_bad_token_key(request), 0) >= limit[0]:
        raise exceptions.Throttled(wait=limit[1], detail="too many invalid tokens from this address; retry later")


def record_bad_token(request) -> None:
    limit = parse_rate(settings.CONTINUUM_THROTTLE_BAD_TOKENS)
    if request is None or limit is None:
        return
    key = _bad_token_key(request)
    cache.add(key, 0, timeout=limit[1])  # the window starts at the first failure
    try:
        cache.incr(key)
    except ValueError:  # expired between add and incr
        cache.set(key, 1, timeout=limit[1])
