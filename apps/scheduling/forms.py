"""The dashboard's schedule and compare forms: presentation layers over the API's request contracts
(:class:`~apps.scheduling.serializers.ScheduleRequestSerializer`, :class:`CompareRequestSerializer`), which
validate them and give the jobs their arguments. The forms add the page's way of naming a target (one of the
fleet's clusters, or N CPUs + M GPUs, turned into a ``continuum.platform/v1`` document)."""

from __future__ import annotations

from django import forms

from apps.clusters.models import Cluster
from apps.ui.forms import SerializerForm, contract_field, json_object, preselect_only
from apps.workloads.models import Application
from continuum.engine.core import limits
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import CLASSES, Platform
from continuum.engine.device import algorithms
from continuum.engine.device.board import board

from .serializers import FRAME_OPTIONS, CompareRequestSerializer, ScheduleRequestSerializer, TargetSerializer

#: The maxima of README "Limits" (continuum/engine/core/limits.py), the same as the API's.
LIMITS = limits.get()


class TargetForm(SerializerForm):
    """Where to schedule (one of the fleet's clusters, or N CPUs + M GPUs) and for how many frames."""

    TARGETS = [("cluster", "a cluster (its Ready nodes)"), ("platform", "a model platform")]
    NAMED = "named"
    serializer_class: type[TargetSerializer] = TargetSerializer

    target = forms.ChoiceField(choices=TARGETS, widget=forms.RadioSelect, initial="platform")
    cluster = forms.ModelChoiceField(queryset=None, required=False, empty_label="— choose a cluster —")
    cpus = forms.IntegerField(min_value=0, max_value=LIMITS.processors, initial=4, required=False, label="CPUs")
    gpus = forms.IntegerField(min_value=0, max_value=LIMITS.processors, initial=0, required=False, label="GPUs")
    shared_memory = forms.BooleanField(
        required=False,
        label="one board (shared memory)",
        help_text="only CPU-GPU transfers cost, as on the thesis' CPU+iGPU boards",
    )
    frames = contract_field(TargetSerializer, "frames", help_text="pipelined frames")
    fps = contract_field(TargetSerializer, "fps", label="FPS", help_text="camera rate (frame f at f/fps)")
    period = contract_field(TargetSerializer, "period", help_text="or a frame period, in the DAG's time unit")
    batch = contract_field(TargetSerializer, "batch", help_text="frames released together")

    FRAME_FIELDS = FRAME_OPTIONS

    def __init__(self, *args, application: Application, request=None, **kwargs):
        super().__init__(*args, **kwargs)
        self.application = application
        self.request = request  # the contract sees only the clusters of the user's fleets
        clusters = Cluster.objects.filter(fleet_id=application.fleet_id)
        self.fields["cluster"].queryset = clusters
        # A DAG that gives its costs per named processor (Topcuoglu's p0, p1, p2) runs only on those: offer
        # them as a target, and choose it, since no cluster node or model CPU/GPU bears those names.
        costs = [task.get("cost") or {} for task in (application.dag or {}).get("tasks", [])]
        self.named_platform = Platform.named_by(costs)
        if self.named_platform is not None:
            names = ", ".join(p.id for p in self.named_platform.processors)
            self.fields["target"].choices = [(self.NAMED, f"the processors its costs name ({names})"), *self.TARGETS]
        # Defaults that make a first attempt work: the DAG's own processors, else the only cluster (or the
        # first one with a Ready node), else a model platform.
        ready = clusters.filter(nodes__status="Ready").distinct().order_by("name")
        if self.named_platform is not None and not _class_costs_everywhere(costs):
            self.fields["target"].initial = self.NAMED
        elif clusters.exists():
            self.fields["target"].initial = "cluster"
        if clusters.exists():
            preselect_only(self.fields["cluster"], fallback=ready.first())

    def serializer_context(self) -> dict:
        return {"application": self.application, "request": self.request}

    def serializer_data(self, data: dict) -> dict:
        payload = {k: data[k] for k in FRAME_OPTIONS if data.get(k) is not None}
        if data.get("target") == "cluster" and data.get("cluster") is not None:
            payload["cluster"] = data["cluster"].pk
        elif data.get("platform") is not None:
            payload["platform"] = data["platform"]
        return payload

    def clean(self):
        # The page's target (a cluster, or CPUs and GPUs) becomes the contract's cluster or platform document.
        data = forms.Form.clean(self)
        target = data.get("target")
        if target == "cluster" and data.get("cluster") is None and "cluster" not in self.errors:
            self.add_error("cluster", "choose a cluster")
        elif target == self.NAMED and self.named_platform is not None:
            data["platform"] = self.named_platform.to_dict()
        elif target == "platform" and not self.errors:
            cpus, gpus = data.get("cpus") or 0, data.get("gpus") or 0
            try:
                platform = board(cpus, gpus) if data.get("shared_memory") else Platform.homogeneous(cpus, gpus)
                data["platform"] = platform.to_dict()
            except InputError as exc:
                self.add_error("cpus", "need at least one processor" if cpus + gpus == 0 else str(exc))
        return super().clean()

    def validated(self, serializer, data: dict) -> None:
        # Catch a cluster without a Ready node, or a task that no processor can run, now rather than in a
        # failed job.
        for field, message in serializer.runnable_errors().items():
            self.add_error(field, message)

    def frame_options(self) -> dict:
        return self.serializer.frame_options()

    def target_arguments(self) -> dict:
        return self.serializer.target_args()


def _class_costs_everywhere(costs: list[dict]) -> bool:
    """Whether every task has a cost for a processor class (so a model platform can run it)."""
    return all(any(key in CLASSES for key in cost) for cost in costs)


class ScheduleForm(TargetForm):
    """Schedule an application with one algorithm, for one frame or several."""

    serializer_class = ScheduleRequestSerializer

    algorithm = contract_field(
        ScheduleRequestSerializer,
        "algorithm",
        required=True,
        choices=[(name, name.upper()) for name in sorted(algorithms.SCHEDULERS)],
    )
    params = forms.CharField(
        required=False,
        widget=forms.Textarea(attrs={"rows": 2, "placeholder": '{"rank_mode": "mean"}'}),
        help_text="algorithm parameters as a JSON object (optional)",
    )

    field_order = ["algorithm"]

    def clean_params(self) -> dict:
        return json_object(self.cleaned_data.get("params"), "parameters must be a JSON object")

    def serializer_data(self, data: dict) -> dict:
        return super().serializer_data(data) | {"algorithm": data.get("algorithm"), "params": data.get("params") or {}}


class CompareForm(TargetForm):
    """Run several algorithms on an application and compare them."""

    serializer_class = CompareRequestSerializer

    algorithms = contract_field(
        CompareRequestSerializer,
        "algorithms",
        required=True,
        widget=forms.CheckboxSelectMultiple,
        choices=[(name, name.upper()) for name in algorithms.SCHEDULERS],
    )
    rank_mode = contract_field(
        CompareRequestSerializer,
        "rank_mode",
        required=True,
        label="Rank cost",
        help_text="max: the thesis (Fig. 3.1); mean: the literature",
    )
    comm_mode = contract_field(
        CompareRequestSerializer,
        "comm_mode",
        label="Rank transfer",
        help_text="impl: the thesis (spec 01 section 2.1); pairs: the literature (mean over processor pairs)",
    )

    field_order = ["algorithms"]

    def serializer_data(self, data: dict) -> dict:
        chosen = [name for name in algorithms.SCHEDULERS if name in (data.get("algorithms") or ())]  # registry order
        payload = {"algorithms": chosen}
        payload |= {k: data[k] for k in ("rank_mode", "comm_mode") if data.get(k)}
        return super().serializer_data(data) | payload
