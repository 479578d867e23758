"""Application pages: the list with the upload and generate forms, and one application's DAG.

Apps above this one add their panels to the application page (``apps.ui.panels``, host
``"workloads.application"``, slots ``side`` and ``main``): scheduling its forms and schedules, HEFT4K its
remapping history. Panel functions are called as ``fn(request, application, **state)``; ``state`` is what
:func:`application_page` was given (a bound form of the view that re-renders the page, for instance).
"""

from __future__ import annotations

from django.contrib import messages
from django.contrib.auth.decorators import login_required
from django.db.models import Count, IntegerField, OuterRef, Subquery
from django.db.models.functions import Coalesce
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, redirect, render
from django.views.decorators.http import require_POST

from apps.tenancy.scoping import visible_fleets
from apps.ui import charts
from apps.ui.helpers import paginate, scoped
from apps.ui.panels import render_panels
from apps.workloads.forms import GenerateForm, UploadForm

from .models import Application

APPLICATION_PAGE = "workloads.application"


@login_required
def application_list(request: HttpRequest) -> HttpResponse:
    fleets = visible_fleets(request)
    bound = request.method == "POST"
    form = UploadForm(request.POST if bound else None, request.FILES if bound else None, fleets=fleets)
    if bound:
        if form.is_valid():
            app = form.save(request.user)
            messages.success(request, f"Imported {app.name!r}: {app.task_count} tasks, {app.edge_count} edges.")
            for warning in form.cleaned_data.get("warnings", []):
                messages.warning(request, warning)
            return redirect("workloads:application", pk=app.pk)
        return _application_list_page(request, fleets, form, GenerateForm(fleets=fleets), status=400)
    return _application_list_page(request, fleets, form, GenerateForm(fleets=fleets))


@login_required
@require_POST
def application_generate(request: HttpRequest) -> HttpResponse:
    fleets = visible_fleets(request)
    form = GenerateForm(request.POST, fleets=fleets)
    if form.is_valid():
        app = form.save(request.user)
        messages.success(request, f"Generated {app.name!r}: {app.task_count} tasks, {app.edge_count} edges.")
        return redirect("workloads:application", pk=app.pk)
    return _application_list_page(request, fleets, UploadForm(fleets=fleets), form, status=400)


def _application_list_page(request, fleets, upload: UploadForm, generate: GenerateForm, status: int = 200):
    # The small columns only (never the DAG JSON) and the schedule count from a correlated subquery: a
    # GROUP BY over the joined rows groups by every selected column on SQLite, the DAG included (issue 13).
    # (The schedules app sits above this one: its model is reached through the reverse relation's name, as the
    # Count("schedules") this replaces did.)
    schedule_model = Application._meta.get_field("schedules").related_model
    schedules = (
        schedule_model.objects.filter(application=OuterRef("pk"))
        .order_by()
        .values("application")
        .annotate(n=Count("pk"))
    )
    apps = (
        scoped(request, Application.objects.select_related("fleet"))
        .only(*Application.LIST_FIELDS, "fleet__id", "fleet__name")
        .annotate(schedule_count=Coalesce(Subquery(schedules.values("n"), output_field=IntegerField()), 0))
        .order_by("-created", "-pk")
    )
    return render(
        request,
        "workloads/application_list.html",
        {
            "page": paginate(request, apps),
            "form": upload,
            "generate": generate,
            "has_fleet": fleets.exists(),
            "nav": "applications",
        },
        status=status,
    )


@login_required
def application_detail(request: HttpRequest, pk: int) -> HttpResponse:
    app = get_object_or_404(scoped(request, Application.objects.select_related("fleet")), pk=pk)
    return application_page(request, app)


def application_page(request: HttpRequest, app: Application, status: int = 200, **state) -> HttpResponse:
    """The application page with every registered panel; ``state`` goes to the panels."""
    graph = app.graph
    return render(
        request,
        "workloads/application_detail.html",
        {
            "app": app,
            "graph": graph,
            "figure": charts.to_html(charts.dag_figure(graph), div_id="dag-chart"),
            "panels": render_panels(APPLICATION_PAGE, request, app, **state),
            "nav": "applications",
        },
        status=status,
    )
