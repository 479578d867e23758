"""Helpers every page of the dashboard shares: fleet scoping and pagination."""

from __future__ import annotations

from django.core.paginator import Page, Paginator
from django.db.models import QuerySet
from django.http import HttpRequest

from apps.tenancy.scoping import visible_fleets

PAGE_SIZE = 25


def scoped(request: HttpRequest, qs: QuerySet, lookup: str = "fleet") -> QuerySet:
    """``qs`` limited to the fleets the user may see."""
    return qs.filter(**{f"{lookup}__in": visible_fleets(request)})


def paginate(request: HttpRequest, qs: QuerySet) -> Page:
    """The page of ``qs`` the request's ``?page=`` asks for, :data:`PAGE_SIZE` rows a page."""
    return Paginator(qs, PAGE_SIZE).get_page(request.GET.get("page"))
