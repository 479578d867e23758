"""The client's address, as the throttles, the login limiter and the audit trail see it.

``X-Forwarded-For`` is written by whoever sends the request, so it is believed only as far as trusted proxies
wrote it: with ``CONTINUUM_NUM_PROXIES = n`` (REST framework's ``NUM_PROXIES``), the address is the n-th entry
from the right of that header (each proxy appends the address it received the request from); with 0, the
default, it is the connection's own address (``REMOTE_ADDR``) and the header is ignored. Issue 25: trusting the
header let anyone spend a robot's per-address budget, or a new forged address per request escape every one.
"""

from __future__ import annotations

from django.conf import settings


def num_proxies() -> int:
    return int(getattr(settings, "CONTINUUM_NUM_PROXIES", 0) or 0)


def client_address(request) -> str:
    """The address the request came from (see the module docstring); "" when unknown."""
    meta = getattr(request, "META", None) or {}
    remote = meta.get("REMOTE_ADDR") or ""
    proxies = num_proxies()
    forwarded = meta.get("HTTP_X_FORWARDED_FOR")
    if proxies <= 0 or not forwarded:
        return remote
    hops = [h.strip() for h in forwarded.split(",")]
    # Fewer entries than proxies: the request skipped a proxy, so the header is the caller's own; the
    # connection's address is then the only one to trust.
    if len(hops) < proxies:
        return remote
    return hops[-proxies][:64] or remote
