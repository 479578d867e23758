"""Fleet isolation, checked on every endpoint the API router has (found by drf-spectacular's endpoint
enumerator, so new endpoints are covered without editing this file).

Two fleets get the same kinds of data (mostly made through the API and its jobs, the rest filled in
generically). Fleet B's token then asks about fleet A's objects, and each answer must equal, byte for byte
once the id itself is normalised, the answer for an id that does not exist:

- every route with an id in its path (detail routes and detail actions, every method, and OPTIONS);
- every filter parameter of every list endpoint (A's value of the filtered field vs a value nobody has);
- every writable related field of every request serializer (A's object vs no object), starting from one of
  B's own objects as the API shows it so that the request gets as far as validate();
- every declared query parameter of an action that names an object (``?cluster=``);
- and the browsable API's HTML pages (lists, and B's own objects with their edit forms) never name one of A's
  objects.

A static check also walks every serializer of the apps and every filterset: each related field and
model-choice filter must offer fleet B none of fleet A's objects.
"""

from __future__ import annotations

import inspect
import json
import re
import uuid
from types import SimpleNamespace

import pytest
from django.apps import apps as django_apps
from django.contrib.auth.models import AnonymousUser
from django.core.files.uploadedfile import SimpleUploadedFile
from django.db import models, transaction
from django.utils import timezone
from django_filters import filters as django_filters
from drf_spectacular.generators import EndpointEnumerator, SchemaGenerator
from rest_framework import serializers
from rest_framework.parsers import JSONParser
from rest_framework.test import APIClient

from apps.tenancy.api import FleetScopedSerializerMixin
from apps.tenancy.filters import FleetScopedFilterBackend
from apps.tenancy.models import Fleet, FleetToken
from apps.tenancy.scoping import fleet_path, is_global, scope
from tests.conftest import DATA
from tests.heft4k.fan import FAN_DAG

#: Every name in fleet A contains TAG_A, and nothing of fleet B does (so an HTML page can be searched).
TAG_A, TAG_B = "acmefleet", "bravofleet"
#: An id no object has.
MISSING = 987654321
WRITE_METHODS = ("POST", "PUT", "PATCH")


# ---- the endpoints ----------------------------------------------------------------------------------------
def _endpoints() -> list[tuple]:
    """(path with {params}, METHOD, view class, action, view function) of every /api/v1/ endpoint."""
    generator = SchemaGenerator()
    found = []
    for path, _regex, method, callback in EndpointEnumerator().get_api_endpoints():
        if not path.startswith("/api/v1/"):
            continue
        view = generator.create_view(callback, method)
        found.append((path, method, type(view), getattr(view, "action", None), callback))
    return found


ENDPOINTS = _endpoints()
ID_ENDPOINTS = [e for e in ENDPOINTS if "{" in e[0]]
WRITE_ENDPOINTS = [e for e in ENDPOINTS if e[1] in WRITE_METHODS]
LIST_ENDPOINTS = [e for e in ENDPOINTS if e[1] == "GET" and e[3] == "list"]
GET_ENDPOINTS = [e for e in ENDPOINTS if e[1] == "GET"]


def _ids(endpoints) -> list[str]:
    return [f"{method} {path}" for path, method, *_ in endpoints]


def view_model(view_class) -> type[models.Model] | None:
    queryset = getattr(view_class, "queryset", None)
    return queryset.model if queryset is not None else None


# ---- the world: two fleets with data ----------------------------------------------------------------------
def _client(token: FleetToken) -> APIClient:
    client = APIClient()
    client.credentials(HTTP_AUTHORIZATION=f"Token {token.plaintext}")
    return client


def _ok(response, status=(200, 201, 202)):
    assert response.status_code in status, (response.status_code, getattr(response, "data", response.content))
    return response.data


def _job(client, url: str, body: dict) -> dict:
    job = _ok(client.post(url, body, format="json"), (202,))
    job = client.get(f"/api/v1/jobs/{job['id']}/").data
    assert job["state"] == "succeeded", job
    return job


def _populate(client: APIClient, fleet: Fleet, tag: str) -> None:
    """One of everything, made the way users make it (API calls and the jobs they start)."""
    nodes = [
        {"name": f"{tag}-node{i}", "cpu": 4, "memory_mib": 8192, "rt": i < 3, "criticality": "A" if i < 2 else "C"}
        for i in range(4)
    ]
    links = [{"src": f"{tag}-node{i}", "dst": f"{tag}-node{i + 1}", "bandwidth_mbps": 1000} for i in range(3)]
    cluster = _ok(
        client.post("/api/v1/clusters/import/", {"name": f"{tag}-edge", "nodes": nodes, "links": links}, format="json")
    )
    app = _ok(client.post("/api/v1/applications/", {"name": f"{tag}-fan", "dag": FAN_DAG}, format="json"))
    job = _job(client, f"/api/v1/applications/{app['id']}/schedule/", {"algorithm": "heft4k", "cluster": cluster["id"]})
    _job(client, f"/api/v1/schedules/{job['result']['schedule']}/remap/", {"fail": [f"{tag}-node1"], "what_if": True})
    compare = {"cluster": cluster["id"], "algorithms": ["heft", "heft4k"]}
    _job(client, f"/api/v1/applications/{app['id']}/compare/", compare)

    graph = (DATA / "autoware_reference_system.json").read_bytes()
    upload = SimpleUploadedFile(f"{tag}.json", graph)
    rosgraph = _ok(
        client.post("/api/v1/rosgraphs/import/", {"file": upload, "name": f"{tag}-graph"}, format="multipart")
    )
    job = _job(client, f"/api/v1/rosgraphs/{rosgraph['id']}/cluster/", {"containers": 4})
    _job(client, f"/api/v1/clusterings/{job['result']['clustering']}/place/", {"cluster": cluster["id"]})

    wcets = [{"node": f"{tag}-node0", "wcet": 12}, {"node": f"{tag}-node1", "wcet": 8}]
    _ok(
        client.post(
            "/api/v1/realtimes/",
            {
                "cluster": cluster["id"],
                "name": f"{tag}-rt",
                "criticality": "A",
                "period": 100,
                "deadline": 100,
                "wcets": wcets,
            },
            format="json",
        )
    )
    _ok(client.post("/api/v1/rt-policies/", {"cluster": cluster["id"]}, format="json"))
    spec = {
        "node": f"{tag}-node0",
        "containerName": f"{tag}-slam",
        "missedDeadlinesPeriod": 50,
        "missedDeadlinesTotal": 50,
    }
    _ok(client.post("/api/v1/rt-reports/", {"cluster": cluster["id"], "reports": [spec]}, format="json"))
    _job(client, "/api/v1/rt-plans/whatif/", {"cluster": cluster["id"]})

    assertion = _ok(
        client.post(
            "/api/v1/assertions/",
            {"name": f"{tag}-arrives", "text": "G(speed > 0 -> F[0,5000](arrived))"},
            format="json",
        )
    )
    node0 = client.get("/api/v1/nodes/", {"name": f"{tag}-node0"}).data["results"][0]["id"]
    monitor = _ok(
        client.post(
            "/api/v1/monitors/",
            {"assertion": assertion["id"], "cluster": cluster["id"], "name": f"{tag}-monitor", "node": node0},
            format="json",
        )
    )
    events = [["speed", 5.0, 0], ["speed", 0, 6000], ["speed", 0, 6500]]
    _ok(client.post("/api/v1/events/", {"cluster": cluster["id"], "events": events}, format="json"))
    _ok(client.post(f"/api/v1/monitors/{monitor['id']}/finish/"))
    fill_missing(fleet, tag)


def _value(field: models.Field, tag: str):
    if field.choices:
        return field.choices[0][0]
    if isinstance(field, models.UUIDField):
        return uuid.uuid4()
    if isinstance(field, models.CharField | models.TextField):
        return f"{tag}-{field.model._meta.model_name}-{field.name}"[: field.max_length or 200]
    if isinstance(field, models.BooleanField):
        return False
    if isinstance(field, models.IntegerField | models.FloatField | models.DecimalField):
        return 1
    if isinstance(field, models.DateTimeField):
        return timezone.now()
    if isinstance(field, models.JSONField):
        return {}
    raise NotImplementedError(f"{field.model.__name__}.{field.name}: no generic value for {type(field).__name__}")


#: Optional fields make() fills anyway: names (the HTML check looks for the tag) and ids (filters use them).
FILLED = ("name", "key", "title")


def make(model: type[models.Model], fleet: Fleet, tag: str) -> models.Model:
    """A row of ``model`` in ``fleet``: required fields get plain values (names carry the fleet's tag) and
    relations the fleet's existing objects (required ones made as needed)."""
    values = {}
    for field in model._meta.concrete_fields:
        if field.primary_key or getattr(field, "auto_now", False) or getattr(field, "auto_now_add", False):
            continue
        if field.is_relation:
            target = field.related_model
            if target is Fleet:
                values[field.name] = fleet
            elif fleet_path(target) or not field.null:
                # Optional relations too (when the fleet has a candidate): filters on them get exercised.
                candidates = target.objects.filter(**_in_fleet(target, fleet))
                if field.one_to_one:
                    candidates = candidates.exclude(pk__in=model.objects.values(field.attname))
                found = candidates.first()
                if found is not None or not field.null:
                    values[field.name] = found or make(target, fleet, tag)
        elif not (field.has_default() or field.null) or field.name in FILLED or isinstance(field, models.UUIDField):
            values[field.name] = _value(field, tag)
    return model.objects.create(**values)


def _in_fleet(model, fleet) -> dict:
    path = fleet_path(model)
    return {path: fleet.pk} if path and path != "pk" else {"pk": fleet.pk} if path == "pk" else {}


def fill_missing(fleet: Fleet, tag: str) -> None:
    """At least one object of every endpoint's model in ``fleet`` (endpoints added later are covered too)."""
    for _path, _method, view_class, _action, _cb in ENDPOINTS:
        model = view_model(view_class)
        if model is None or is_global(model) or model is Fleet:
            continue
        if not model.objects.filter(**_in_fleet(model, fleet)).exists():
            make(model, fleet, tag)


@pytest.fixture(scope="module")
def world(django_db_setup, django_db_blocker):
    """Fleets A and B with data and tokens; made once for the module and rolled back at its end."""
    with django_db_blocker.unblock():
        atomic = transaction.atomic()
        atomic.__enter__()
        try:
            from django.contrib.auth import get_user_model

            users = get_user_model().objects
            world = {}
            for key, tag in (("a", TAG_A), ("b", TAG_B)):
                fleet = Fleet.objects.create(name=f"{tag} fleet")
                token = FleetToken.objects.create(fleet=fleet, user=users.create_user(f"robot-{key}"))
                _populate(_client(token), fleet, tag)
                world[key] = SimpleNamespace(
                    fleet=fleet, token=token, request=SimpleNamespace(auth=token, user=token.user)
                )
            yield world
        finally:
            transaction.set_rollback(True)
            atomic.__exit__(None, None, None)


@pytest.fixture
def b_client(world, db) -> APIClient:
    return _client(world["b"].token)


def first_of(model, side) -> models.Model | None:
    return scope(model.objects.all(), side.request).order_by("pk").first()


# ---- comparing answers ------------------------------------------------------------------------------------
def answer(client: APIClient, method: str, url: str, *, normalise=(), **kwargs) -> tuple:
    """(status, content type, body with the given values replaced by a marker), with every side effect of the
    request rolled back (a leak may write)."""
    with transaction.atomic():
        response = getattr(client, method.lower())(url, **kwargs)
        transaction.set_rollback(True)
    body = response.content.decode("utf-8", "replace")
    for value in normalise:
        body = re.sub(rf"(?<![\w-]){re.escape(str(value))}(?![\w-])", "<ID>", body)
    return response.status_code, response.get("Content-Type"), body


def url_for(path: str, value) -> str:
    return re.sub(r"\{\w+\}", str(value), path)


def missing_value(model, field_name: str = "pk") -> str:
    """A value of ``model``'s field (its pk by default) that no object has, of the right type."""
    field = model._meta.pk if field_name == "pk" else model._meta.get_field(field_name)
    if isinstance(field, models.UUIDField):
        return str(uuid.UUID(int=MISSING))
    if isinstance(field, models.IntegerField | models.AutoField):
        return str(MISSING)
    return "no-such-object"


def lookup_value(view_class, obj) -> str:
    field = getattr(view_class, "lookup_field", "pk")
    return str(getattr(obj, field))


# ---- 1. routes with an id ---------------------------------------------------------------------------------
def _fleet_owned(endpoint) -> bool:
    model = view_model(endpoint[2])
    return model is not None and not is_global(model)


# Routes of models every fleet shares (device profiles) or with no model have nothing to leak by id.
OWNED_ID_ENDPOINTS = [e for e in ID_ENDPOINTS if _fleet_owned(e)]


@pytest.mark.parametrize(
    ("path", "method", "view_class", "action", "callback"), OWNED_ID_ENDPOINTS, ids=_ids(OWNED_ID_ENDPOINTS)
)
def test_another_fleets_id_in_the_path_answers_like_no_such_id(
    world, b_client, path, method, view_class, action, callback
):
    model = view_model(view_class)
    theirs = first_of(model, world["a"])
    assert theirs is not None, f"the world has no {model.__name__} in fleet A"
    their_id = lookup_value(view_class, theirs)
    missing = missing_value(model, getattr(view_class, "lookup_field", "pk"))
    kwargs = {"data": {}, "format": "json"} if method in WRITE_METHODS else {}
    leak = answer(b_client, method, url_for(path, their_id), normalise=[their_id], **kwargs)
    none = answer(b_client, method, url_for(path, missing), normalise=[missing], **kwargs)
    assert leak == none
    if action == "retrieve":  # the metadata of OPTIONS, too; it names no object, so nothing is normalised
        # (an id of 2 would otherwise be "normalised" out of the view's description, "Algorithm 2")
        leak = answer(b_client, "OPTIONS", url_for(path, their_id))
        none = answer(b_client, "OPTIONS", url_for(path, missing))
        assert leak == none


# ---- 2. filters -------------------------------------------------------------------------------------------
#: Filters whose values are ids or free text: for another fleet's value they must answer as for a value
#: nobody has. (Choice and boolean filters take public enumerations.)
SECRET_FILTERS = (
    django_filters.ModelChoiceFilter,
    django_filters.ModelMultipleChoiceFilter,
    django_filters.NumberFilter,
    django_filters.CharFilter,
    django_filters.UUIDFilter,
)


def _filters(view_class):
    model = view_model(view_class)
    if model is None:
        return {}
    view = view_class()
    filterset_class = FleetScopedFilterBackend().get_filterset_class(view, model.objects.none())
    return filterset_class.base_filters if filterset_class else {}


def _bogus(flt) -> str:
    if isinstance(flt, django_filters.CharFilter) and not isinstance(flt, django_filters.NumberFilter):
        return "no-such-value"
    if isinstance(flt, django_filters.UUIDFilter):
        return str(uuid.UUID(int=MISSING))
    return str(MISSING)


@pytest.mark.parametrize(
    ("path", "method", "view_class", "action", "callback"), LIST_ENDPOINTS, ids=_ids(LIST_ENDPOINTS)
)
def test_filters_answer_for_another_fleets_value_like_for_no_value(
    world, b_client, path, method, view_class, action, callback
):
    model = view_model(view_class)
    checked = 0
    for name, flt in _filters(view_class).items():
        if not isinstance(flt, SECRET_FILTERS) or is_global(model):
            continue
        field = flt.field_name
        theirs = scope(model.objects.all(), world["a"].request).exclude(**{f"{field}__isnull": True})
        values = list(theirs.values_list(field, flat=True).distinct()[:3])
        ours = set(scope(model.objects.all(), world["b"].request).values_list(field, flat=True))
        values = [v for v in values if v not in ours and v not in ("", None)]
        if not values:
            continue
        value, bogus = str(values[0]), _bogus(flt)
        leak = answer(b_client, "GET", path, data={name: value}, normalise=[value])
        none = answer(b_client, "GET", path, data={name: bogus}, normalise=[bogus])
        assert leak == none, f"filter {name}={value}"
        checked += 1
    if any(isinstance(f, django_filters.ModelChoiceFilter) for f in _filters(view_class).values()):
        assert checked, "no model-choice filter was exercised: the world lacks fleet A data for this endpoint"


# ---- 3. related fields of request serializers -------------------------------------------------------------
#: Generators and views made for request_serializer(), kept alive: the generator owns the views' schemas,
#: which it hands out as weak references.
_KEEP = []


def request_serializer(callback, method: str, b_request):
    generator = SchemaGenerator()
    view = generator.create_view(callback, method)
    _KEEP.append((generator, view))
    view.request = b_request
    view.format_kwarg = None
    view.kwargs = {}
    found = view.schema.get_request_serializer()
    if isinstance(found, dict):
        found = next((s for s in found.values() if s is not None), None)
    if found is None:
        return None
    return found if isinstance(found, serializers.BaseSerializer) else found()


def related_fields(serializer) -> dict[str, serializers.Field]:
    out = {}
    for name, field in serializer.fields.items():
        if field.read_only:
            continue
        relation = field.child_relation if isinstance(field, serializers.ManyRelatedField) else field
        if isinstance(relation, serializers.RelatedField):
            out[name] = field
    return out


def _related_value(field, obj):
    relation = field.child_relation if isinstance(field, serializers.ManyRelatedField) else field
    value = getattr(obj, relation.slug_field) if isinstance(relation, serializers.SlugRelatedField) else obj.pk
    return [value] if isinstance(field, serializers.ManyRelatedField) else value


def _own_representation(client, path: str, view_class, action, side, serializer) -> dict:
    model = view_model(view_class)
    if action not in ("create", "update", "partial_update") or model is None or not hasattr(view_class, "retrieve"):
        return {}
    mine = first_of(model, side)
    if mine is None:
        return {}
    detail = path if "{" in path else f"{path}{{pk}}/"
    response = client.get(url_for(detail, lookup_value(view_class, mine)))
    if response.status_code != 200:
        return {}
    writable = {name for name, f in serializer.fields.items() if not f.read_only}
    return {k: v for k, v in response.json().items() if k in writable}


def _field_model(field):
    relation = field.child_relation if isinstance(field, serializers.ManyRelatedField) else field
    relation.context  # noqa: B018 (bound: the queryset may need it)
    queryset = relation.get_queryset()
    return queryset.model


def _takes_related_fields(endpoint) -> bool:
    """Whether the write endpoint's request body has a writable related field (found without a caller: the
    fields themselves do not depend on who asks, only their querysets do)."""
    _path, method, _view, _action, callback = endpoint
    anonymous = SimpleNamespace(auth=None, user=AnonymousUser(), method=method, query_params={}, data={})
    serializer = request_serializer(callback, method, anonymous)
    return serializer is not None and bool(related_fields(serializer))


RELATED_WRITE_ENDPOINTS = [e for e in WRITE_ENDPOINTS if _takes_related_fields(e)]


@pytest.mark.parametrize(
    ("path", "method", "view_class", "action", "callback"), RELATED_WRITE_ENDPOINTS, ids=_ids(RELATED_WRITE_ENDPOINTS)
)
def test_related_fields_answer_for_another_fleets_object_like_for_no_object(
    world, b_client, path, method, view_class, action, callback
):
    b = world["b"]
    fake = SimpleNamespace(auth=b.token, user=b.token.user, method=method, query_params={}, data={})
    serializer = request_serializer(callback, method, fake)
    serializer._context = {"request": fake}
    fields = related_fields(serializer)
    assert fields
    url = path
    if "{" in path:
        model = view_model(view_class)
        mine = first_of(model, b) if model is not None else None
        if mine is None:
            pytest.skip("no object of fleet B to address")
        url = url_for(path, lookup_value(view_class, mine))
    models_of = {name: _field_model(f) for name, f in fields.items()}
    # Start from one of B's own objects as the API shows it (for the model's create and update) and let the
    # other related fields name B's objects, so the request gets as far as validation can take it.
    base = _own_representation(b_client, path, view_class, action, b, serializer)
    for name, field in fields.items():
        mine = first_of(models_of[name], b)
        if mine is not None:
            base[name] = _related_value(field, mine)
    parsers = getattr(view_class, "parser_classes", [])
    fmt = "json" if any(issubclass(p, JSONParser) for p in parsers) else "multipart"
    for name, field in fields.items():
        model = models_of[name]
        if is_global(model):
            continue
        theirs = first_of(model, world["a"])
        assert theirs is not None, f"the world has no {model.__name__} in fleet A"
        their_value = _related_value(field, theirs)
        bogus = [MISSING] if isinstance(field, serializers.ManyRelatedField) else MISSING
        if isinstance(field, serializers.SlugRelatedField):
            bogus = "no-such-object"
        shown = their_value[0] if isinstance(their_value, list) else their_value
        leak = answer(b_client, method, url, data={**base, name: their_value}, format=fmt, normalise=[shown])
        none = answer(
            b_client,
            method,
            url,
            data={**base, name: bogus},
            format=fmt,
            normalise=[bogus[0] if isinstance(bogus, list) else bogus],
        )
        assert leak == none, f"{name}={their_value!r}"


# ---- 4. the browsable API ---------------------------------------------------------------------------------
@pytest.mark.parametrize(("path", "method", "view_class", "action", "callback"), GET_ENDPOINTS, ids=_ids(GET_ENDPOINTS))
def test_browsable_api_pages_name_none_of_another_fleets_objects(
    world, b_client, path, method, view_class, action, callback
):
    url = path
    if "{" in path:
        model = view_model(view_class)
        mine = first_of(model, world["b"]) if model is not None else None
        if mine is None:
            pytest.skip("no object of fleet B to show")
        url = url_for(path, lookup_value(view_class, mine))
    response = b_client.get(url, HTTP_ACCEPT="text/html")
    body = b"".join(response.streaming_content) if response.streaming else response.content  # exports stream
    assert response.status_code < 500, body[:2000]
    html = body.decode("utf-8", "replace")
    if action == "list" and response.status_code == 200:  # B has objects here: the check is not vacuous
        data = b_client.get(url).json()
        assert (data["count"] if isinstance(data, dict) else len(data)) > 0, "fleet B has nothing here"
    assert TAG_A not in html, re.findall(rf".{{0,80}}{TAG_A}.{{0,40}}", html)[:5]


# ---- 5. query parameters of actions that name an object -------------------------------------------------
def _models_by_name() -> dict[str, type[models.Model]]:
    return {m._meta.model_name: m for m in django_apps.get_models() if m._meta.app_label != "auth"}


def _id_parameters(callback, method: str) -> list[tuple[str, type[models.Model]]]:
    """Declared query parameters (extend_schema) whose name is a model's, e.g. ``?cluster=`` of an action."""
    generator = SchemaGenerator()
    view = generator.create_view(callback, method)
    _KEEP.append((generator, view))
    by_name = _models_by_name()
    return [(p.name, by_name[p.name]) for p in view.schema.get_override_parameters() if p.name in by_name]


# Actions (GET, beyond list and retrieve) with a query parameter that names an object, e.g. ?cluster=.
ACTION_GETS = [e for e in GET_ENDPOINTS if e[3] not in ("list", "retrieve") and _id_parameters(e[4], e[1])]


@pytest.mark.parametrize(("path", "method", "view_class", "action", "callback"), ACTION_GETS, ids=_ids(ACTION_GETS))
def test_action_query_parameters_answer_for_another_fleets_object_like_for_no_object(
    world, b_client, path, method, view_class, action, callback
):
    parameters = _id_parameters(callback, method)
    assert parameters
    url = path
    if "{" in path:
        url = url_for(path, lookup_value(view_class, first_of(view_model(view_class), world["b"])))
    for name, model in parameters:
        theirs = str(first_of(model, world["a"]).pk)
        missing = missing_value(model)
        leak = answer(b_client, method, url, data={name: theirs}, normalise=[theirs])
        none = answer(b_client, method, url, data={name: missing}, normalise=[missing])
        assert leak == none, f"?{name}={theirs}"


# ---- 6. static check: serializers and filtersets --------------------------------------------------------
def _app_serializers() -> list[type[serializers.BaseSerializer]]:
    found = set()
    for config in django_apps.get_app_configs():
        if not config.name.startswith("apps."):
            continue
        for module_name in ("serializers", "api"):
            try:
                module = __import__(f"{config.name}.{module_name}", fromlist=["_"])
            except ModuleNotFoundError:
                continue
            for obj in vars(module).values():
                if (
                    inspect.isclass(obj)
                    and issubclass(obj, serializers.BaseSerializer)
                    and obj.__module__ == module.__name__
                ):
                    found.add(obj)
    return sorted(found, key=lambda c: f"{c.__module__}.{c.__name__}")


def _walk_related(serializer, prefix=""):
    for name, field in serializer.fields.items():
        if isinstance(field, serializers.ListSerializer):
            field = field.child
        if isinstance(field, serializers.BaseSerializer):
            yield from _walk_related(field, f"{prefix}{name}.")
            continue
        if isinstance(field, serializers.ManyRelatedField):
            field = field.child_relation
        if isinstance(field, serializers.RelatedField) and not field.read_only:
            yield f"{prefix}{name}", field


def test_every_serializer_of_the_apps_scopes_its_related_fields(world, db):
    a, b = world["a"], world["b"]
    classes = _app_serializers()
    assert len(classes) > 30
    problems, checked = [], 0
    for cls in classes:
        if not issubclass(cls, FleetScopedSerializerMixin):
            problems.append(f"{cls.__module__}.{cls.__name__} does not derive from ScopedSerializer")
            continue
        try:
            serializer = cls(context={"request": b.request})
            related = list(_walk_related(serializer))
        except (TypeError, AssertionError, KeyError):
            continue  # an abstract base (no Meta) or one that needs more context to exist
        for name, field in related:
            model = field.get_queryset().model
            if is_global(model):
                continue
            if fleet_path(model) is None:
                problems.append(f"{cls.__name__}.{name}: {model.__name__} belongs to no fleet and is not global")
                continue
            theirs = scope(model.objects.all(), a.request).values("pk")
            assert theirs.exists(), f"the world has no {model.__name__} in fleet A"
            if field.get_queryset().filter(pk__in=theirs).exists():
                problems.append(f"{cls.__name__}.{name} offers fleet A's {model.__name__} objects to fleet B")
            checked += 1
    assert not problems, problems
    assert checked > 10


def test_every_filterset_scopes_its_model_choice_filters(world, db):
    a, b = world["a"], world["b"]
    backend = FleetScopedFilterBackend()
    problems, checked = [], 0
    for _path, _method, view_class, action, _cb in LIST_ENDPOINTS:
        model = view_model(view_class)
        if model is None:
            continue
        view = view_class()
        view.request, view.action = b.request, action
        filterset = backend.get_filterset(
            SimpleNamespace(**vars(b.request), query_params={}), model.objects.none(), view
        )
        if filterset is None:
            continue
        for name, flt in filterset.filters.items():
            if not isinstance(flt, django_filters.QuerySetRequestMixin):
                continue
            queryset = flt.get_queryset(b.request)
            theirs = scope(queryset.model.objects.all(), a.request).values("pk")
            if queryset.filter(pk__in=theirs).exists():
                problems.append(f"{view_class.__name__} filter {name} offers fleet A's objects to fleet B")
            checked += 1
    assert not problems, problems
    assert checked > 20


def test_the_endpoint_walk_finds_the_whole_api():
    """A guard against the discovery silently finding nothing."""
    assert len(ENDPOINTS) > 80 and len(ID_ENDPOINTS) > 40 and len(LIST_ENDPOINTS) > 25
    assert json.dumps(sorted({p.split("/")[3] for p, *_ in ENDPOINTS}))  # every resource has a name


def test_browsable_api_forms_list_at_most_html_cutoff_choices(api, cluster):
    """A fleet with many nodes: the link form's node selects stop at HTML_CUTOFF (one bounded query each), and
    the filter form takes ids instead of listing every node."""
    from apps.clusters.models import ComputeNode
    from apps.tenancy.api import HTML_CUTOFF

    ComputeNode.objects.bulk_create(ComputeNode(cluster=cluster, name=f"bulk{i:03d}") for i in range(HTML_CUTOFF + 50))
    response = api.get("/api/v1/links/", HTTP_ACCEPT="text/html")
    assert response.status_code == 200
    html = response.content.decode()
    assert f"More than {HTML_CUTOFF} items" in html
    shown = set(re.findall(r"bulk\d{3}", html))
    assert 0 < len(shown) <= HTML_CUTOFF
    assert 'name="src" value=""' in html or re.search(r'<input[^>]+name="src"', html)


def test_fleet_paths_follow_the_shortest_required_foreign_keys():
    from django.contrib.auth import get_user_model

    from apps.clusters.models import ComputeNode, Link
    from apps.containers.models import Placement
    from apps.devices.models import DeviceProfile
    from apps.verification.models import Handler, Violation

    assert fleet_path(Fleet) == "pk"
    assert fleet_path(Placement) == "fleet"  # not through its optional cluster
    assert fleet_path(ComputeNode) == fleet_path(Link) == fleet_path(Handler) == "cluster__fleet"
    assert fleet_path(Violation) == "monitor__fleet"
    assert fleet_path(get_user_model()) is None  # scope() then answers nothing
    assert is_global(DeviceProfile) and not is_global(ComputeNode)
