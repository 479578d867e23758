"""The API's side of :mod:`continuum.engine.core.limits`: bounded pagination, a JSON body parser that checks
depth/NaN/NUL before recursing, and a middleware that turns a NUL in the query string into a 400.

Each answers a hostile input with a 400 naming the parameter, where Django/DRF/PostgreSQL would otherwise
raise (``?limit=99999999999999999999`` overflows a PostgreSQL bigint; a NUL reaches PostgreSQL, which
refuses it; ``[[[[...`` 100k deep exhausts Python's recursion limit).
"""

from __future__ import annotations

import codecs

from django import forms
from django.conf import settings
from django.http import JsonResponse
from rest_framework.exceptions import ParseError, ValidationError
from rest_framework.fields import FileField
from rest_framework.pagination import LimitOffsetPagination
from rest_framework.parsers import FormParser, JSONParser, MultiPartParser

from continuum.engine.core import limits
from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import loads_json

#: int() refuses more digits than this anyway; far more than any real offset.
_MAX_DIGITS = 18


def _bounded_int(request, name: str, default: int | None, maximum: int | None) -> int | None:
    raw = request.query_params.get(name)
    if raw is None or raw == "":
        return default
    raw = raw.strip()
    if not raw.isdigit() or len(raw) > _MAX_DIGITS:
        raise ValidationError({name: [f"must be a whole number from 0 to {maximum or 10**_MAX_DIGITS - 1}"]})
    value = int(raw)
    if maximum is not None and value > maximum:
        raise ValidationError({name: [f"{name}: at most {maximum}"]})
    return value


def at_most(name: str) -> dict[str, str]:
    """``error_messages`` for a bounded serializer field: "frames: at most 1000", like the engine's."""
    return {"max_value": f"{name}: at most {{max_value}}"}


def at_most_items(name: str) -> dict[str, str]:
    """``error_messages`` for a bounded list (serializer ``many=True``/ListField): "nodes: at most 5000"."""
    return {"max_length": f"{name}: at most {{max_length}}"}


class BoundedLimitOffsetPagination(LimitOffsetPagination):
    """``limit`` at most ``limits.page_size`` (a larger one is a 400 naming it), ``offset`` a bounded
    whole number; anything else is a 400 rather than DRF's silent fallback or a database overflow."""

    @property
    def max_limit(self) -> int:  # read per request, so CONTINUUM_MAX_PAGE_SIZE and overrides apply
        return limits.get().page_size

    def get_limit(self, request):
        if self.limit_query_param not in request.query_params:
            return self.default_limit
        value = _bounded_int(request, self.limit_query_param, self.default_limit, self.max_limit)
        if value == 0:
            raise ValidationError({self.limit_query_param: ["must be at least 1"]})
        return value

    def get_offset(self, request):
        return _bounded_int(request, self.offset_query_param, 0, 10**_MAX_DIGITS - 1) or 0


class SafeJSONParser(JSONParser):
    """DRF's JSON parser through :func:`continuum.engine.core.safeload.loads_json`: too deep, NaN/Infinity,
    1e400 or NUL is a 400, and the body size is bounded by DATA_UPLOAD_MAX_MEMORY_SIZE (Django)."""

    def parse(self, stream, media_type=None, parser_context=None):
        parser_context = parser_context or {}
        encoding = parser_context.get("encoding", settings.DEFAULT_CHARSET)
        try:
            text = codecs.getreader(encoding)(stream).read()
        except UnicodeDecodeError as exc:
            raise ParseError(f"JSON parse error - not {encoding} text") from exc
        try:
            return loads_json(text)
        except InputError as exc:
            if exc.field:  # a refused value (NaN, 1e400, NUL): a field error naming its path
                raise ValidationError({exc.field: [str(exc)]}) from exc
            raise ParseError(f"JSON parse error - {exc}") from exc


def _reject_nul_fields(data) -> None:
    """A NUL, or its JSON escape (a form field may be parsed as JSON, e.g. a node's labels), is a 400 on
    that field."""
    for key, values in data.lists():
        if "\x00" in key or any(isinstance(v, str) and ("\x00" in v or "\\u0000" in v) for v in values):
            raise ValidationError({key.replace("\x00", "\\0"): ["must not contain a NUL character"]})


class SafeFormParser(FormParser):
    """Form bodies: a NUL in any field is a 400 (PostgreSQL text and jsonb hold none)."""

    def parse(self, stream, media_type=None, parser_context=None):
        data = super().parse(stream, media_type, parser_context)
        _reject_nul_fields(data)
        return data


class SafeMultiPartParser(MultiPartParser):
    """Multipart bodies: a NUL in any (non-file) field is a 400; files are checked by their readers."""

    def parse(self, stream, media_type=None, parser_context=None):
        result = super().parse(stream, media_type, parser_context)
        _reject_nul_fields(result.data)
        return result


#: Bytes a body that carries a file of ``limits.upload_bytes`` may have beyond it: the multipart framing and
#: the form's other fields. The file itself is held to ``upload_bytes`` by its field (a 400 naming it).
UPLOAD_FRAMING_BYTES = 64 * 1024


def body_limit(view_func, method: str) -> int:
    """The most bytes a request body may have at this view: ``limits.upload_bytes`` (plus the framing of a
    multipart body) for the actions a DRF view lists in ``document_actions`` (they take a document or a file)
    and for the dashboard's pages (their forms upload files), ``limits.body_bytes`` for every other API
    action."""
    lim = limits.get()
    cls = getattr(view_func, "cls", None)
    if cls is None:  # not DRF: a dashboard page or the admin
        return lim.upload_bytes + UPLOAD_FRAMING_BYTES
    actions = getattr(view_func, "actions", None) or {}
    action = actions.get(method.lower(), method.lower())
    if action in getattr(cls, "document_actions", ()):
        return lim.upload_bytes + UPLOAD_FRAMING_BYTES
    return lim.body_bytes


class BodyLimitMiddleware:
    """Refuse a request body above its endpoint's limit (:func:`body_limit`) with 413 naming the limit, before
    any parser, authentication or CSRF check reads it (``process_view`` runs ahead of the CSRF middleware's).

    The declared ``Content-Length`` is what is checked: Django reads a body only up to it (a request without
    one has an empty body, chunked bodies included), so a body can never grow past what was checked here."""

    def __init__(self, get_response):
        self.get_response = get_response

    def __call__(self, request):
        return self.get_response(request)

    def process_view(self, request, view_func, view_args, view_kwargs):
        raw = request.META.get("CONTENT_LENGTH") or "0"
        if not raw.isdigit() or len(raw) > _MAX_DIGITS:
            return JsonResponse({"detail": "Content-Length must be a whole number of bytes"}, status=400)
        size, limit = int(raw), body_limit(view_func, request.method or "GET")
        if size > limit:
            return too_large(limit, size)
        return None


def too_large(limit: int, size: int | None = None) -> JsonResponse:
    """413 naming the endpoint's body limit (and the size sent, when known)."""
    got = f" (got {size:,})" if size is not None else ""
    return JsonResponse(
        {"detail": f"request body: at most {limit:,} bytes at this endpoint{got}", "limit_bytes": limit}, status=413
    )


class RejectNulMiddleware:
    """A NUL character in a query parameter (``?search=%00``) is a 400 naming the parameter; PostgreSQL
    would refuse it with an error that surfaces as a 500."""

    def __init__(self, get_response):
        self.get_response = get_response

    def __call__(self, request):
        for key, values in request.GET.lists():
            if "\x00" in key or any("\x00" in v for v in values):
                name = key.replace("\x00", "\\0")
                return JsonResponse({name: ["must not contain a NUL character"]}, status=400)
        if "\x00" in request.path:
            return JsonResponse({"detail": "the path must not contain a NUL character"}, status=400)
        return self.get_response(request)


def upload_too_large(upload, name: str = "file") -> str | None:
    """The message for an uploaded file above ``limits.upload_bytes``, else None. Django's
    DATA_UPLOAD_MAX_MEMORY_SIZE leaves file parts out, so every import field checks here."""
    maximum = limits.get().upload_bytes
    size = getattr(upload, "size", None) or 0
    if size > maximum:
        return f"{name}: at most {maximum:,} bytes (got {size:,})"
    return None


class BoundedFileField(FileField):
    """A file upload of at most ``limits.upload_bytes`` (README, "Limits")."""

    def to_internal_value(self, data):
        upload = super().to_internal_value(data)
        message = upload_too_large(upload, self.field_name or "file")
        if message:
            raise ValidationError(message)
        return upload


class BoundedFormFileField(forms.FileField):
    """The dashboard's upload field with the same bound."""

    def clean(self, data, initial=None):
        upload = super().clean(data, initial)
        message = upload_too_large(upload) if upload else None
        if message:
            raise forms.ValidationError(message)
        return upload
