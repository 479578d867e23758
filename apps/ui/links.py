"""Which page shows a finished job's result, registered by the apps that own the pages, so that the job
pages (``apps.jobs``, below them) name none of them.

A job's result names what it made by a key (``{"schedule": 12}``, ``{"remap": 3}``); the app that owns the
page registers the key with its URL name. Keys are tried by ``order`` (a remap also names its new schedule:
the remap page wins). A job may also name its page itself (``{"page": "/ros/clusterings/4/"}``), tried at
:data:`PAGE_ORDER`.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

from django.db.models import Model
from django.urls import reverse

#: Where a job's own ``page`` comes among the registered keys.
PAGE_ORDER = 30

_RESULT_PAGES: dict[str, tuple[int, str]] = {}
#: Pages of the rows a job's arguments name (``{"application": 3}``), by argument name: URL name.
_OBJECT_PAGES: dict[str, str] = {}


def register_result_page(key: str, url_name: str, *, order: int = 100) -> None:
    """An integer ``key`` in a job's result is the pk of an object shown at the URL named ``url_name``."""
    _RESULT_PAGES[key] = (order, url_name)


def result_page(result: Mapping[str, Any]) -> str | None:
    """The page that shows a succeeded job's ``result``, or None when no page is registered for it."""
    own = result.get("page")
    candidates = sorted([*_RESULT_PAGES.items(), ("page", (PAGE_ORDER, ""))], key=lambda kv: (kv[1][0], kv[0]))
    for key, (_, url_name) in candidates:
        value = result.get(key)
        if key == "page" and not url_name:
            if isinstance(own, str) and own.startswith("/"):
                return own  # the job names its dashboard page itself
        elif isinstance(value, int) and not isinstance(value, bool):
            return reverse(url_name, args=[value])
    return None


def register_object_page(key: str, url_name: str) -> None:
    """An integer ``key`` in a job's arguments is the pk of an object shown at the URL named ``url_name``."""
    _OBJECT_PAGES[key] = url_name


def object_page(key: str, value: Any) -> str | None:
    """The page of the row that argument ``key`` names by its pk ``value`` (result keys count too: a
    ``schedule`` argument is shown where a ``schedule`` result is); None when none is registered."""
    url_name = _OBJECT_PAGES.get(key) or _RESULT_PAGES.get(key, (0, ""))[1]
    if not url_name or not isinstance(value, int) or isinstance(value, bool):
        return None
    return reverse(url_name, args=[value])


#: Models whose rows a job's arguments name by pk (``{"application": 3}``), by argument name: shown and searched by
#: their ``name`` (the job pages, below the apps, import none of them).
_OBJECT_MODELS: dict[str, type[Model]] = {}


def register_object_names(key: str, model: type[Model]) -> None:
    """An integer ``key`` in a job's arguments is the pk of a ``model`` row with a ``name``."""
    _OBJECT_MODELS[key] = model


def object_names(key: str, ids: Iterable[Any]) -> dict[int, str]:
    """The names of the rows argument ``key`` names, by pk (empty when none is registered)."""
    model = _OBJECT_MODELS.get(key)
    pks = {int(i) for i in ids if isinstance(i, int | str) and str(i).isdigit()}
    if model is None or not pks:
        return {}
    return dict(model._default_manager.filter(pk__in=pks).values_list("pk", "name"))


def objects_named(key: str, word: str, limit: int = 1000) -> list[int]:
    """The pks of argument ``key``'s rows whose name contains ``word`` (for a search over jobs)."""
    model = _OBJECT_MODELS.get(key)
    if model is None:
        return []
    return list(model._default_manager.filter(name__icontains=word).values_list("pk", flat=True)[:limit])
