"""django-filter, fleet-scoped: every model-choice filter of every list endpoint accepts only objects of the
caller's fleets, so another fleet's id answers exactly like an id that does not exist."""

from django import forms
from django_filters import filters
from django_filters.rest_framework import DjangoFilterBackend

from .scoping import scope


def scoped_queryset(unscoped, model):
    """A django-filter ``queryset`` callable: ``unscoped`` (a queryset, a callable taking the request, or None
    for all of ``model``) limited to the request's fleets."""

    def queryset(request):
        base = unscoped(request) if callable(unscoped) else unscoped
        if base is None:
            base = model._default_manager.all()
        return scope(base, request)

    return queryset


def scope_filterset(filterset) -> None:
    """Scope every model-choice filter of a FilterSet instance (its filters are per-instance copies)."""
    for name, flt in filterset.filters.items():
        if not isinstance(flt, filters.QuerySetRequestMixin) or getattr(flt, "fleet_scoped", False):
            continue
        model = flt.queryset.model if hasattr(flt.queryset, "model") else related_model(filterset, name)
        flt.queryset = scoped_queryset(flt.queryset, model)
        flt.fleet_scoped = True
        if isinstance(flt, filters.ModelChoiceFilter):
            # The browsable API's filter form takes an id: a <select> would render every visible row.
            flt.extra["widget"] = forms.TextInput


def related_model(filterset, name):
    from django_filters.utils import get_model_field

    field = get_model_field(filterset._meta.model, filterset.filters[name].field_name)
    return field.related_model


class FleetScopedFilterBackend(DjangoFilterBackend):
    """DjangoFilterBackend whose filtersets (generated from ``filterset_fields`` or declared) are scoped."""

    def get_filterset(self, request, queryset, view):
        filterset = super().get_filterset(request, queryset, view)
        if filterset is not None:
            scope_filterset(filterset)
        return filterset
