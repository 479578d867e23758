"""Who did what: request ids and the audit trail's actor for token requests.

The audit trail is django-auditlog's (``LogEntry``, in the admin under "Auditlog"); the models it follows are
listed in the settings (``AUDITLOG_INCLUDE_TRACKING_MODELS``), so tenancy imports no domain app. Its
middleware knows the session user; a fleet token is only known once DRF authenticated the request, and
:func:`note_token` then names the token's user, prefix and fleet in the entries the request writes.
Each entry's ``cid`` is the request id, made by the server for every request and sent back in ``X-Request-ID``;
a caller's own ``X-Request-ID`` is never the id (anyone could write any id into the trail), it is kept beside
it as ``client_request_id`` in the entries' additional data and in the response's ``X-Client-Request-ID``.
The address an entry records is the client's (:mod:`apps.tenancy.clientaddr`), not a forged
``X-Forwarded-For``.
"""

from __future__ import annotations

import re
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

from auditlog.context import auditlog_value, set_extra_data
from auditlog.middleware import AuditlogMiddleware

from .clientaddr import client_address, num_proxies

_request_id: ContextVar[str | None] = ContextVar("continuum_request_id", default=None)
_VALID_ID = re.compile(r"^[A-Za-z0-9._-]{1,64}$")


def request_id() -> str | None:
    """The current request's id (``AUDITLOG_CID_GETTER``), None outside a request."""
    return _request_id.get()


def client_request_id(request) -> str | None:
    """The caller's own ``X-Request-ID`` when it is a plain token (letters, digits, ``._-``, at most 64)."""
    given = request.headers.get("X-Request-ID", "")
    return given if _VALID_ID.match(given) else None


class RequestIdMiddleware:
    """Give every request a new id of the server's (a UUID); the caller's ``X-Request-ID`` is kept apart."""

    def __init__(self, get_response):
        self.get_response = get_response

    def __call__(self, request):
        rid = uuid.uuid4().hex
        request.request_id = rid
        request.client_request_id = client_request_id(request)
        reset = _request_id.set(rid)
        try:
            response = self.get_response(request)
        finally:
            _request_id.reset(reset)
        response["X-Request-ID"] = rid
        if request.client_request_id:
            response["X-Client-Request-ID"] = request.client_request_id
        return response


class AuditMiddleware(AuditlogMiddleware):
    """django-auditlog's middleware with the client's address taken as the throttles take it: its own reads
    the first ``X-Forwarded-For`` entry, which the caller writes."""

    @staticmethod
    def _get_remote_addr(request):
        return client_address(request) or None

    @staticmethod
    def _get_remote_port(request) -> int | None:
        if num_proxies() <= 0:
            return None
        return AuditlogMiddleware._get_remote_port(request)

    def get_extra_data(self, request):
        data = super().get_extra_data(request)
        given = getattr(request, "client_request_id", None)
        if given:
            data["additional_data"] = {"client_request_id": given}
        return data


def note_token(token) -> None:
    """Make the token's user the actor of the audit entries this request writes, with the token's prefix."""
    try:
        context = auditlog_value.get()
    except LookupError:  # no AuditlogMiddleware around this call (a command, a test calling a view directly)
        return
    context["actor"] = token.user
    context["additional_data"] = {
        **(context.get("additional_data") or {}),
        "token": token.prefix,
        "fleet": token.fleet.slug,
        "scope": token.scope,
    }


@contextmanager
def acting_for(user, **extra) -> Iterator[None]:
    """Name ``user`` (and ``extra``) in the audit entries written inside, e.g. by a job in a worker on behalf
    of whoever started it. Inside a request the request's own actor stands, and this does nothing (auditlog
    keeps one context per thread, which a nested one would replace)."""
    if user is None or request_id() is not None:
        yield
        return
    with set_extra_data(context_data={"actor": user, "additional_data": extra or None}):
        yield
