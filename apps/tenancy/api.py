"""API building blocks shared by every app: fleet scoping, the fleet field, engine errors as HTTP 400."""

import logging
import uuid
from functools import partial

from django.core.exceptions import (
    ImproperlyConfigured,
    RequestDataTooBig,
    SuspiciousOperation,
    TooManyFieldsSent,
    TooManyFilesSent,
)
from django.db import models
from django.db.models import QuerySet
from drf_spectacular.types import OpenApiTypes
from drf_spectacular.utils import extend_schema_field
from rest_framework import mixins, serializers, status, viewsets
from rest_framework.exceptions import ValidationError
from rest_framework.response import Response
from rest_framework.views import exception_handler as drf_exception_handler
from rest_framework.views import set_rollback

from continuum.engine.core.errors import InputError
from continuum.engine.core.safeload import check_json_value, loads_json

from .audit import request_id
from .models import Fleet, FleetToken
from .scoping import scope, visible_fleets

#: Most choices a browsable-API form lists for one related field (DRF's default is 1000 rows a field).
HTML_CUTOFF = 100

log = logging.getLogger(__name__)


def exception_handler(exc, context):
    """Engine input errors become 400s that name the field and the offending element; anything unexpected
    becomes a 500 with an error id, its traceback logged under that id and never sent to the caller."""
    if isinstance(exc, InputError):
        exc = ValidationError({exc.field or "non_field_errors": [str(exc)]})
    if isinstance(exc, SuspiciousOperation):  # Django's own bounds, met while DRF parses a body
        return _suspicious(exc)
    response = drf_exception_handler(exc, context)
    if response is not None:
        response.data = _printable(response.data)
        return response
    error_id = str(uuid.uuid4())
    request = context.get("request")
    log.error(
        "internal error %s (request %s, %s %s)",
        error_id,
        request_id(),
        getattr(request, "method", "?"),
        getattr(request, "path", "?"),
        exc_info=(type(exc), exc, exc.__traceback__),
    )
    set_rollback()
    return Response({"detail": "internal error", "error_id": error_id}, status=status.HTTP_500_INTERNAL_SERVER_ERROR)


def _printable(data):
    """An error's detail with every lone UTF-16 surrogate written as its escape (``\\ud800``): a message that
    echoes one could not be encoded as UTF-8 and the answer became a 500 (issue 25)."""
    if isinstance(data, str):
        if not data.isascii():
            try:
                data.encode()
            except UnicodeEncodeError:
                fixed = data.encode("utf-8", "backslashreplace").decode()
                return type(data)(fixed, code=data.code) if hasattr(data, "code") else fixed
        return data
    if isinstance(data, dict):
        return {_printable(k): _printable(v) for k, v in data.items()}
    if isinstance(data, list):
        return [_printable(v) for v in data]
    return data


def _suspicious(exc: SuspiciousOperation) -> Response:
    """Django refuses a body it will not parse by raising SuspiciousOperation, which a plain Django view turns
    into a 400 but DRF hands to this handler: the answer names the bound instead of a 500."""
    from django.conf import settings

    set_rollback()
    if isinstance(exc, RequestDataTooBig):
        limit = settings.DATA_UPLOAD_MAX_MEMORY_SIZE
        return Response(
            {"detail": f"request body: at most {limit:,} bytes of form fields", "limit_bytes": limit},
            status=status.HTTP_413_REQUEST_ENTITY_TOO_LARGE,
        )
    if isinstance(exc, TooManyFieldsSent):
        detail = f"at most {settings.DATA_UPLOAD_MAX_NUMBER_FIELDS:,} form fields"
    elif isinstance(exc, TooManyFilesSent):
        detail = f"at most {settings.DATA_UPLOAD_MAX_NUMBER_FILES:,} files"
    else:
        detail = "malformed request"
    return Response({"detail": detail}, status=status.HTTP_400_BAD_REQUEST)


def contract_error(errors, path: str = "") -> InputError:
    """A request serializer's first error as one :class:`InputError` line, ``field: message`` (nested fields
    joined by dots): how a management command that checks its options with the API's request contract
    reports bad input (exit status 2, one line on stderr)."""
    if isinstance(errors, dict):
        field, inner = next(iter(errors.items()))
        name = field if field != "non_field_errors" else ""
        return contract_error(inner, f"{path}.{name}" if path and name else path or name)
    if isinstance(errors, list) and errors and not isinstance(errors[0], str):
        # A list field's errors hold one entry per item, empty for the valid ones: report the first bad item.
        return contract_error(next((e for e in errors if e), errors[0]), path)
    message = str(errors[0]) if isinstance(errors, list) and errors else str(errors)
    field = path.split(".")[-1] if path else None
    return InputError(message if not path or message.startswith(field or "") else f"{path}: {message}", field)


@extend_schema_field(OpenApiTypes.STR)
class FleetField(serializers.SlugRelatedField):
    """The owning fleet by slug, limited to the fleets the caller may see (others are "not found")."""

    def __init__(self, **kwargs):
        kwargs.setdefault("slug_field", "slug")
        super().__init__(**kwargs)

    def get_queryset(self) -> QuerySet[Fleet]:
        return visible_fleets(self.context.get("request"))


class DefaultFleetMixin:
    """``fleet`` defaults to the token's fleet, or to the caller's only fleet."""

    def validate(self, attrs):
        attrs = super().validate(attrs)
        if self.instance is None and "fleet" not in attrs:
            attrs["fleet"] = default_fleet(self.context["request"])
        return attrs


class ChosenFleetMixin:
    """``context["fleet"]``, when given, is the fleet: the dashboard's forms ask for it among the user's fleets
    (``apps.ui.forms.FleetSerializerForm``) and pass it so; ``context["user"]`` is then who stores the result."""

    def validate(self, attrs):
        attrs = super().validate(attrs)
        if "fleet" in self.context:
            attrs["fleet"] = self.context["fleet"]
        return attrs

    def _user(self):
        if "user" in self.context:
            return self.context["user"]
        return self.context["request"].user


@extend_schema_field(OpenApiTypes.INT)
class VisibleRelatedField(serializers.PrimaryKeyRelatedField):
    """An object of the caller's fleets by id; ``model`` is set by a subclass or given as the first argument
    (the path to the fleet is found by ``scoping.fleet_path``). Other fleets' objects are "does not exist",
    like unknown ids."""

    model = None

    def __init__(self, model=None, **kwargs):
        if model is not None:
            self.model = model
        super().__init__(**kwargs)

    def get_queryset(self):
        return scope(self.model.objects.all(), self.context.get("request"))


def _scoped_queryset(field: serializers.RelatedField, unscoped) -> QuerySet:
    queryset = unscoped()
    return scope(queryset, field.context.get("request")) if queryset is not None else None


def scope_field(field: serializers.Field) -> None:
    """Limit a writable related field (or the fields of a nested serializer) to the caller's fleets.

    The field's own ``get_queryset`` is wrapped, so a declared ``queryset=Model.objects.all()``, a ModelSerializer's
    generated field and a custom ``get_queryset`` are all narrowed; choices in HTML forms come from the same
    queryset, cut off at HTML_CUTOFF rows."""
    if isinstance(field, serializers.ListSerializer):
        field = field.child
    if isinstance(field, serializers.BaseSerializer):
        if not isinstance(field, FleetScopedSerializerMixin):
            for child in field.fields.values():
                scope_field(child)
        return
    if isinstance(field, serializers.ManyRelatedField):
        field.html_cutoff = min(field.html_cutoff or HTML_CUTOFF, HTML_CUTOFF)
        field = field.child_relation
    if not isinstance(field, serializers.RelatedField) or field.read_only or getattr(field, "fleet_scoped", False):
        return
    field.get_queryset = partial(_scoped_queryset, field, field.get_queryset)
    field.fleet_scoped = True
    field.html_cutoff = min(field.html_cutoff or HTML_CUTOFF, HTML_CUTOFF)


class FleetScopedSerializerMixin:
    """Every writable related field of the serializer (declared, generated or nested) accepts and lists only
    objects of the caller's fleets."""

    def get_fields(self):
        fields = super().get_fields()
        for field in fields.values():
            scope_field(field)
        return fields


class ScopedSerializer(FleetScopedSerializerMixin, serializers.Serializer):
    """The base of every plain serializer of the API."""


class SafeJSONField(serializers.JSONField):
    """A JSON value that a form field may carry as text too: read with the API's JSON rules (depth, NaN, NUL,
    lone surrogates: :func:`~continuum.engine.core.safeload.loads_json`), and ``null`` refused unless the field
    allows it (issue 25: a form's ``constants=null`` reached a NOT NULL column and answered 500)."""

    def to_internal_value(self, data):
        if getattr(data, "is_json_string", False) and not self.binary:
            try:
                value = loads_json(str(data))
            except InputError as exc:
                raise ValidationError(str(exc)) from None
        else:
            value = super().to_internal_value(data)
            try:
                check_json_value(value)
            except InputError as exc:
                raise ValidationError(str(exc)) from None
        if value is None and not self.allow_null:
            self.fail("null")
        return value


class ScopedModelSerializer(FleetScopedSerializerMixin, serializers.ModelSerializer):
    """The base of every model serializer of the API."""

    serializer_field_mapping = {**serializers.ModelSerializer.serializer_field_mapping, models.JSONField: SafeJSONField}


class FleetOwnedSerializer(DefaultFleetMixin, ScopedModelSerializer):
    fleet = FleetField(required=False)


def default_fleet(request) -> Fleet:
    if isinstance(request.auth, FleetToken):
        return request.auth.fleet
    fleets = list(visible_fleets(request)[:2])
    if len(fleets) == 1:
        return fleets[0]
    raise ValidationError({"fleet": ["name the fleet (slug): you belong to several or none"]})


class FleetScopedMixin:
    """Limit a viewset's queryset to the caller's fleets; objects of other fleets answer 404."""

    #: Lookup path from the model to its fleet; None: found from the model (``scoping.fleet_path``).
    fleet_lookup = None

    def get_queryset(self):
        qs = super().get_queryset()
        if self.fleet_lookup is None:
            return scope(qs, self.request)
        return qs.filter(**{f"{self.fleet_lookup}__in": visible_fleets(self.request)})


# A viewset that apps above it add ``@action`` routes to, the way NetBox plugins extend its views: the host
# never imports its extensions (the extension imports the host, which sits below it). The extending app
# defines the action in its own ``api.py`` and its ``AppConfig.ready()`` imports that module, so the route
# exists before the URLconf is built:
#
#     @ApplicationViewSet.extra_action
#     @extend_schema(request=ScheduleRequestSerializer, responses={202: JobSerializer})
#     @action(detail=True, methods=["post"])
#     def schedule(self, request, pk=None): ...
#
# The route, its name, the OpenAPI operation id and the schema are those of an action written in the host's
# class body. (Comments, not a docstring: drf-spectacular describes operations with the first docstring in
# the viewset's MRO.)
class ExtensibleViewSetMixin:
    @classmethod
    def extra_action(cls, func):
        """Add the ``@action``-decorated ``func`` to this viewset under its own name; returns ``func``."""
        if not hasattr(func, "mapping") or not hasattr(func, "detail"):
            raise ImproperlyConfigured(f"{func.__qualname__} is not decorated with @action")
        current = getattr(cls, func.__name__, None)
        if current is not None and current is not func:
            raise ImproperlyConfigured(f"{cls.__name__} already has an attribute {func.__name__!r}")
        setattr(cls, func.__name__, func)
        return func


class FleetSerializer(ScopedModelSerializer):
    class Meta:
        model = Fleet
        fields = ["id", "name", "slug", "description", "created"]
        read_only_fields = ["slug", "created"]


class FleetViewSet(mixins.ListModelMixin, mixins.RetrieveModelMixin, viewsets.GenericViewSet):
    """The fleets the caller belongs to (fleets are created by administrators)."""

    serializer_class = FleetSerializer
    queryset = Fleet.objects.all()
    search_fields = ["name", "slug"]

    def get_queryset(self):
        return visible_fleets(self.request)
