"""Who did what: request ids and the audit trail's actor for token requests.

The audit trail is django-auditlog's (``LogEntry``, in the admin under "Auditlog"); the models it follows are
listed in the settings (``AUDITLOG_INCLUDE_TRACKING_MODELS``), so tenancy imports no domain app. Its
middleware knows the session user; a fleet token is only known once DRF authenticated the request, and
:func:`note_token` then names the token's user, prefix and fleet in the entries the request writes.
Each entry's ``cid`` is the request id (the ``X-Request-ID`` header, echoed back, or a new one).
"""

from __future__ import annotations

import re
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

from auditlog.context import auditlog_value, set_extra_data

_request_id: ContextVar[str | None] = ContextVar("continuum_request_id", default=None)
_VALID_ID = re.compile(r"^[A-Za-z0-9._-]{1,64}$")


def request_id() -> str | None:
    """The current request's id (``AUDITLOG_CID_GETTER``), None outside a request."""
    return _request_id.get()


class RequestIdMiddleware:
    """Give every request an id: the caller's ``X-Request-ID`` when it is a plain token, else a new UUID."""

    def __init__(self, get_response):
        self.get_response = get_response

    def __call__(self, request):
        given = request.headers.get("X-Request-ID", "")
        rid = given if _VALID_ID.match(given) else uuid.uuid4().hex
        request.request_id = rid
        reset = _request_id.set(rid)
        try:
            response = self.get_response(request)
        finally:
            _request_id.reset(reset)
        response["X-Request-ID"] = rid
        return response


def note_token(token) -> None:
    """Make the token's user the actor of the audit entries this request writes, with the token's prefix."""
    try:
        context = auditlog_value.get()
    except LookupError:  # no AuditlogMiddleware around this call (a command, a test calling a view directly)
        return
    context["actor"] = token.user
    context["additional_data"] = {"token": token.prefix, "fleet": token.fleet.slug, "scope": token.scope}


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
