"""Forms of the HEFT4K pages."""

from __future__ import annotations

from django import forms
from django.conf import settings

from apps.scheduling.models import Schedule
from continuum.engine.core.errors import InputError

from . import remapping
from .models import RemapEvent


class WhatIfForm(forms.Form):
    """Fail one node of a schedule and see Algorithm 2's remap before anything is pushed."""

    node = forms.ChoiceField(label="Fail node")
    threshold = forms.FloatField(
        required=False,
        min_value=0,
        max_value=100,
        label="Threshold (%)",
        help_text="total remap when the lost share of the HEFT ranks exceeds this",
    )

    def __init__(self, *args, schedule: Schedule, **kwargs):
        super().__init__(*args, **kwargs)
        self.schedule = schedule
        counts: dict[str, int] = {}
        for processor in schedule.assignments.values_list("processor", flat=True):
            counts[processor] = counts.get(processor, 0) + 1
        self.fields["node"].choices = [
            (n, f"{n} ({counts.get(n, 0)} task{'s' if counts.get(n, 0) != 1 else ''})")
            for n in remapping.schedule_nodes(schedule)
        ]
        self.fields["threshold"].initial = round(100 * settings.CONTINUUM_REMAP_THRESHOLD, 6)
        self.fields["threshold"].widget.attrs["step"] = "any"

    def clean(self):
        data = super().clean()
        if "node" not in data:
            return data
        threshold = data.get("threshold")
        data["fraction"] = None if threshold is None else threshold / 100.0
        try:
            remapping.check(self.schedule, [data["node"]], data["fraction"])
        except InputError as exc:
            self.add_error("threshold" if exc.field == "threshold" else "node", str(exc))
        return data

    def job_arguments(self) -> dict:
        return {
            "schedule": self.schedule.pk,
            "fail": [self.cleaned_data["node"]],
            "what_if": True,
            "threshold": self.cleaned_data["fraction"],
            "trigger": RemapEvent.Trigger.WHAT_IF,
        }
