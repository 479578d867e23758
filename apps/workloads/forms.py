"""The dashboard's application forms (upload a DAG file, generate a synthetic DAG): presentation layers over
the API's request contracts, :class:`~apps.workloads.serializers.ApplicationImportSerializer` and
:class:`~apps.workloads.serializers.ApplicationGenerateSerializer`, which validate them and store the result.
The fleet is asked for only when the user has several."""

from __future__ import annotations

import json

from django import forms

from apps.tenancy.bounds import BoundedFormFileField
from apps.ui.forms import FleetSerializerForm, contract_field, errors_onto
from continuum.engine.core import limits
from continuum.engine.device.generators import SHAPES

from .importing import FORMATS
from .serializers import ApplicationGenerateSerializer, ApplicationImportSerializer

FORMAT_HELP = "continuum JSON, WfCommons WfFormat 1.5, Pegasus DAX (.dax/.xml), Kasahara STG (.stg), thesis CSV (.csv)"
#: STG reader options (``continuum.engine.formats.stg``) offered as form fields (the API's ``options``).
STG_OPTIONS = ("ccr", "processors", "heterogeneity", "seed")

#: The maxima of README "Limits" (continuum/engine/core/limits.py), the same as the API's.
LIMITS = limits.get()


class UploadForm(FleetSerializerForm):
    """A DAG file in any supported format; the fleet is asked for only when the user has several."""

    serializer_class = ApplicationImportSerializer

    file = BoundedFormFileField(help_text=FORMAT_HELP)
    format = contract_field(
        ApplicationImportSerializer,
        "format",
        choices=[("", "from the file name or content"), *((f, f) for f in FORMATS)],
        label="Format",
    )
    name = contract_field(ApplicationImportSerializer, "name", help_text="default: the name in the file")
    # The reader options (the API's ``options`` JSON object), one field each.
    ccr = forms.FloatField(min_value=0, required=False, label="CCR", help_text="communication-to-computation ratio")
    processors = forms.IntegerField(
        min_value=1,
        max_value=LIMITS.processors,
        required=False,
        help_text="cost per processor p0.. (unrelated machines)",
    )
    heterogeneity = forms.FloatField(min_value=0, max_value=2, required=False, help_text="beta, 0 to 2")
    seed = forms.IntegerField(min_value=0, required=False, help_text="for the drawn data and costs")
    duplicate = forms.BooleanField(
        required=False,
        label="store it again if this file was uploaded before",
        help_text="otherwise a file the fleet holds already is refused, with a link to its application",
    )
    fleet = forms.ModelChoiceField(queryset=None, required=True, empty_label=None)

    def serializer_context(self) -> dict:
        # Kept, so that the page can link to the application a refused duplicate is stored as.
        self.contract_context = super().serializer_context()
        return self.contract_context

    @property
    def duplicate_of(self):
        return getattr(self, "contract_context", {}).get("duplicate_of")

    def serializer_data(self, data: dict) -> dict:
        payload = {k: data[k] for k in ("file", "format", "name") if data.get(k) not in (None, "")}
        if data.get("duplicate"):
            payload["duplicate"] = "allow"
        options = {k: data[k] for k in STG_OPTIONS if data.get(k) is not None}
        if options:
            payload["options"] = json.dumps(options)
        return payload

    def add_serializer_errors(self, errors) -> None:
        errors = dict(errors)
        for message in errors.pop("options", []):
            self.add_error(None, f"STG options: {message}")
        errors_onto(self, errors)

    def validated(self, serializer, data: dict) -> None:
        data["warnings"] = serializer.validated_data["warnings"]  # shown once, not stored


class GenerateForm(FleetSerializerForm):
    """A seeded synthetic DAG: the thesis' Tree/Linear CPU/GPU DAGs or the HEFT literature's layered graphs."""

    serializer_class = ApplicationGenerateSerializer

    GENERATORS = [
        ("thesis", "thesis: OpenVX-like CPU/GPU DAG (Tree or Linear)"),
        ("layered", "layered: random DAG of the HEFT literature"),
    ]
    generator = contract_field(
        ApplicationGenerateSerializer,
        "generator",
        choices=GENERATORS,
        initial="thesis",
        required=True,
        widget=forms.RadioSelect,
    )
    n = contract_field(ApplicationGenerateSerializer, "n", label="Tasks", help_text="default: drawn")
    seed = contract_field(ApplicationGenerateSerializer, "seed", required=True, help_text="")
    dag_class = contract_field(
        ApplicationGenerateSerializer,
        "dag_class",
        choices=[("", "drawn from the seed"), *((s, s) for s in SHAPES)],
        label="Class (thesis)",
        help_text="",
    )
    ccr = contract_field(ApplicationGenerateSerializer, "ccr", label="CCR (layered)", help_text="")
    processors = contract_field(
        ApplicationGenerateSerializer, "processors", label="Processors (layered)", help_text="unrelated costs p0.."
    )
    heterogeneity = contract_field(
        ApplicationGenerateSerializer, "heterogeneity", label="Heterogeneity (layered)", help_text=""
    )
    fleet = forms.ModelChoiceField(queryset=None, required=True, empty_label=None)

    def serializer_data(self, data: dict) -> dict:
        keys = ("generator", "n", "seed", "dag_class", "ccr", "processors", "heterogeneity")
        return {k: data[k] for k in keys if data.get(k) not in (None, "")}
