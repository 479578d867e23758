"""The verification page's simulation form: the API's simulate request
(:class:`~.serializers.SimulationRequestSerializer`) as a form, plus the fleet that stores the result."""

from __future__ import annotations

from django import forms

from apps.ui.forms import SerializerForm, contract_field

from .serializers import SimulationRequestSerializer


class SimulationForm(SerializerForm):
    serializer_class = SimulationRequestSerializer

    scenario = contract_field(
        SimulationRequestSerializer,
        "scenario",
        required=True,
        choices=[("kairos", "RB-Kairos (§4.5.2, Fig. 4.24)"), ("synthetic", "Three-level cluster (§4.5.1, Fig. 4.22)")],
    )
    fleet = forms.ModelChoiceField(queryset=None, empty_label=None)

    def __init__(self, *args, fleets, **kwargs):
        super().__init__(*args, **kwargs)
        self.fields["fleet"].queryset = fleets
        if fleets.count() == 1:
            self.fields["fleet"].widget = forms.HiddenInput()
            self.fields["fleet"].initial = fleets.first().pk
