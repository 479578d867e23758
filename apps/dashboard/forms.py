"""Dashboard forms: DAG upload and scheduling. Both validate with the engine, so errors name the culprit."""

from __future__ import annotations

import json

from django import forms

from apps.clusters.models import Cluster
from apps.workloads.models import Application
from apps.workloads.serializers import FORMATS
from continuum.engine import algorithms
from continuum.engine.errors import InputError
from continuum.engine.formats import load_dag
from continuum.engine.platform import Platform


class UploadForm(forms.Form):
    """A DAG file in any supported format; the fleet is asked for only when the user has several."""

    file = forms.FileField(help_text="continuum.dag/v1 JSON or a WfCommons WfFormat 1.5 instance")
    format = forms.ChoiceField(
        choices=[("", "guess from the file"), *((f, f) for f in FORMATS)], required=False, label="Format"
    )
    name = forms.CharField(max_length=200, required=False, help_text="default: the name in the file")
    fleet = forms.ModelChoiceField(queryset=None, required=True, empty_label=None)

    def __init__(self, *args, fleets, **kwargs):
        super().__init__(*args, **kwargs)
        self.fields["fleet"].queryset = fleets
        self.fleets = fleets
        self.single_fleet = fleets.count() == 1
        if self.single_fleet:
            # The only possible fleet: no question to ask.
            self.fields["fleet"].initial = fleets.first()
            self.fields["fleet"].required = False
            self.fields["fleet"].widget = forms.HiddenInput()

    def clean(self):
        data = super().clean()
        if not self.fleets.exists():
            raise forms.ValidationError("you are not a member of any fleet, so there is nowhere to store it")
        if self.single_fleet and not data.get("fleet") and "fleet" not in self.errors:
            data["fleet"] = self.fleets.first()
        upload = data.get("file")
        if upload is None:
            return data
        try:
            data["graph"] = load_dag(upload.read(), data.get("format") or None, name=data.get("name") or None)
        except InputError as exc:
            self.add_error("file", f"{upload.name}: {exc}")
        return data

    def save(self, user) -> Application:
        graph = self.cleaned_data["graph"]
        app = Application(
            fleet=self.cleaned_data["fleet"],
            name=graph.name,
            source_format=self.cleaned_data.get("format") or graph.meta.get("source_format", "continuum"),
            created_by=user,
        )
        app.set_graph(graph)
        app.save()
        return app


class ScheduleForm(forms.Form):
    """Schedule an application on one of its fleet's clusters or on N CPUs + M GPUs."""

    TARGETS = [("cluster", "a cluster (its Ready nodes)"), ("platform", "a model platform")]

    algorithm = forms.ChoiceField(choices=[], initial="heft")
    target = forms.ChoiceField(choices=TARGETS, widget=forms.RadioSelect, initial="platform")
    cluster = forms.ModelChoiceField(queryset=None, required=False, empty_label="— choose a cluster —")
    cpus = forms.IntegerField(min_value=0, max_value=4096, initial=4, required=False, label="CPUs")
    gpus = forms.IntegerField(min_value=0, max_value=4096, initial=0, required=False, label="GPUs")
    params = forms.CharField(
        required=False,
        widget=forms.Textarea(attrs={"rows": 2, "placeholder": '{"rank_mode": "mean"}'}),
        help_text="algorithm parameters as a JSON object (optional)",
    )

    def __init__(self, *args, application: Application, **kwargs):
        super().__init__(*args, **kwargs)
        self.application = application
        self.fields["algorithm"].choices = [(name, name.upper()) for name in sorted(algorithms.SCHEDULERS)]
        self.fields["cluster"].queryset = Cluster.objects.filter(fleet_id=application.fleet_id)
        if self.fields["cluster"].queryset.exists():
            self.fields["target"].initial = "cluster"

    def clean_params(self) -> dict:
        text = (self.cleaned_data.get("params") or "").strip()
        if not text:
            return {}
        try:
            value = json.loads(text)
        except json.JSONDecodeError as exc:
            raise forms.ValidationError(f"not JSON (line {exc.lineno} column {exc.colno}: {exc.msg})") from exc
        if not isinstance(value, dict):
            raise forms.ValidationError("parameters must be a JSON object")
        return value

    def clean(self):
        data = super().clean()
        target = data.get("target")
        if target == "cluster":
            cluster = data.get("cluster")
            if cluster is None:
                self.add_error("cluster", "choose a cluster")
                return data
            platform = cluster.to_platform() if cluster.nodes.filter(status="Ready").exists() else None
            if platform is None:
                self.add_error("cluster", f"cluster {cluster.name!r} has no Ready node")
                return data
        elif target == "platform":
            try:
                platform = Platform.homogeneous(data.get("cpus") or 0, data.get("gpus") or 0)
            except InputError as exc:
                self.add_error("cpus", str(exc).replace(" (--cpus/--gpus)", ""))
                return data
            data["platform"] = platform.to_dict()
        else:
            return data
        # Catch a task that no processor can run now rather than in a failed job.
        try:
            platform.cost_table(self.application.graph)
        except InputError as exc:
            self.add_error(None, f"cannot schedule on this target: {exc}")
        return data

    def job_arguments(self) -> dict:
        data = self.cleaned_data
        arguments = {"application": self.application.pk, "algorithm": data["algorithm"], "params": data["params"]}
        if data["target"] == "cluster":
            arguments["cluster"] = data["cluster"].pk
        else:
            arguments["platform"] = data["platform"]
        return arguments
