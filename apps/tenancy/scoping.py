"""Which fleets a request may see (the one behind a fleet token, else the user's memberships), and the
querysets of any model limited to them. Every related field and filter of the API goes through
``scope()``: another fleet's object is then indistinguishable from one that does not exist."""

from __future__ import annotations

from collections import deque
from functools import cache

from django.db import models
from django.db.models import QuerySet

from .models import Fleet, FleetToken

#: Models shared by every fleet (read by all callers); their querysets are not narrowed.
GLOBAL_MODELS = frozenset({"devices.deviceprofile"})


def visible_fleets(request) -> QuerySet[Fleet]:
    if isinstance(getattr(request, "auth", None), FleetToken):
        return Fleet.objects.filter(pk=request.auth.fleet_id)
    user = getattr(request, "user", None)
    if user is None or not user.is_authenticated:
        return Fleet.objects.none()
    if user.is_superuser:
        return Fleet.objects.all()
    return Fleet.objects.filter(members=user)


def is_global(model: type[models.Model]) -> bool:
    return model._meta.label_lower in GLOBAL_MODELS


@cache
def fleet_path(model: type[models.Model]) -> str | None:
    """The ORM lookup from ``model`` to its owning Fleet ("fleet", "cluster__fleet", "pk" for Fleet itself),
    found by following forward foreign keys, shortest path first and required keys before nullable ones;
    None when the model belongs to no fleet."""
    if model is Fleet:
        return "pk"
    queue = deque([(model, "", False)])
    seen = {model}
    best = None
    while queue:
        current, prefix, nullable = queue.popleft()
        for field in current._meta.get_fields():
            if not (field.is_relation and field.concrete and (field.many_to_one or field.one_to_one)):
                continue
            target = field.related_model
            path = f"{prefix}{field.name}"
            through_null = nullable or field.null
            if target is Fleet:
                candidate = (path.count("__"), through_null, path)
                best = min(best, candidate) if best else candidate
            elif target not in seen and not is_global(target):
                seen.add(target)
                queue.append((target, f"{path}__", through_null))
    return best[2] if best else None


def scope(queryset: QuerySet, request) -> QuerySet:
    """``queryset`` limited to the objects of the fleets ``request`` may see. Global models pass unchanged;
    a model that belongs to no fleet and is not global yields nothing (fail closed)."""
    model = queryset.model
    if is_global(model):
        return queryset
    path = fleet_path(model)
    if path is None or request is None:
        return queryset.none()
    if path == "pk":
        return queryset.filter(pk__in=visible_fleets(request).values("pk"))
    return queryset.filter(**{f"{path}__in": visible_fleets(request).values("pk")})
