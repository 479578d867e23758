"""Helpers every page of the dashboard shares: fleet scoping, pagination and the lists' ``?search=``."""

from __future__ import annotations

from collections.abc import Sequence
from functools import reduce
from operator import and_, or_

from django.core.paginator import Page, Paginator
from django.db.models import Q, QuerySet
from django.http import HttpRequest

from apps.tenancy.scoping import visible_fleets

PAGE_SIZE = 25


def scoped(request: HttpRequest, qs: QuerySet, lookup: str = "fleet") -> QuerySet:
    """``qs`` limited to the fleets the user may see."""
    return qs.filter(**{f"{lookup}__in": visible_fleets(request)})


def paginate(request: HttpRequest, qs: QuerySet) -> Page:
    """The page of ``qs`` the request's ``?page=`` asks for, :data:`PAGE_SIZE` rows a page."""
    return Paginator(qs, PAGE_SIZE).get_page(request.GET.get("page"))


#: The longest search text taken (longer is cut): a search is a few words, not a document.
MAX_SEARCH = 100


def search_term(request: HttpRequest) -> str:
    """The list's ``?search=`` text (the API's parameter name), stripped and bounded."""
    return request.GET.get("search", "").strip()[:MAX_SEARCH]


def search_q(term: str, fields: Sequence[str]) -> Q:
    """What DRF's SearchFilter does with ``search_fields``, so a list page and its API answer alike: every word
    of ``term`` must be contained (case-insensitive) in at least one of ``fields``."""
    words = term.split()
    if not words:
        return Q()
    return reduce(and_, (reduce(or_, (Q(**{f"{f}__icontains": w}) for f in fields)) for w in words))
