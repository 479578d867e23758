"""Device pages: the boards and the UMA advisor (which model to use for zero-copy or the cache). Login
required; device profiles are shared by every fleet."""

from __future__ import annotations

from django.contrib.auth.decorators import login_required
from django.http import HttpRequest, HttpResponse
from django.shortcuts import get_object_or_404, render

from apps.devices.forms import AdviceForm
from apps.ui import charts
from continuum.engine.core.errors import InputError

from . import charts as device_charts
from .api import advice
from .models import DeviceProfile
from .serializers import AdviceRequestSerializer


@login_required
def device_list(request: HttpRequest) -> HttpResponse:
    return render(request, "devices/device_list.html", {"devices": DeviceProfile.objects.all(), "nav": "devices"})


@login_required
def device_detail(request: HttpRequest, slug: str) -> HttpResponse:
    device = get_object_or_404(DeviceProfile, slug=slug)
    form = AdviceForm(request.POST if request.method == "POST" else None, device=device)
    answer = None
    status = 200
    if request.method == "POST":
        status = 400
        if form.is_valid():
            serializer = AdviceRequestSerializer(data=form.request_data(), context={"device": device})
            if serializer.is_valid():
                try:
                    answer = advice(device, serializer)
                    status = 200
                except InputError as exc:
                    form.add_error(exc.field if exc.field in form.fields else None, str(exc))
            else:
                for field, errors in serializer.errors.items():
                    for error in errors:
                        form.add_error(field if field in form.fields else None, str(error))
    figure = device_charts.uma_zone_figure(
        device.cpu_threshold_pct,
        device.gpu_threshold_low_pct,
        device.gpu_threshold_high_pct,
        answer["advice"]["cpu_usage"] if answer else None,
        answer["advice"]["gpu_usage"] if answer else None,
    )
    return render(
        request,
        "devices/device_detail.html",
        {
            "device": device,
            "form": form,
            "answer": answer,
            "figure": charts.to_html(figure, div_id="zone-chart"),
            "nav": "devices",
        },
        status=status,
    )
