"""Dashboard forms: DAG upload and generation, scheduling, comparison and the UMA advisor. They validate with
the engine (and the API's serializers), so errors name the culprit."""

from __future__ import annotations

from django import forms

from apps.clusters.models import Cluster
from apps.tenancy.bounds import BoundedFormFileField
from apps.workloads.importing import FORMATS, generate_dag, read_dag_file
from apps.workloads.models import Application
from continuum.engine.core import limits
from continuum.engine.core.errors import InputError
from continuum.engine.core.platform import Platform
from continuum.engine.core.safeload import loads_json
from continuum.engine.device import algorithms
from continuum.engine.device.board import board
from continuum.engine.device.compare import DEFAULT_ALGORITHMS
from continuum.engine.device.generators import SHAPES
from continuum.engine.device.heft import RANK_MODES

FORMAT_HELP = "continuum JSON, WfCommons WfFormat 1.5, Pegasus DAX (.dax/.xml), Kasahara STG (.stg), thesis CSV (.csv)"
#: STG reader options (``continuum.engine.formats.stg``) offered as form fields.
STG_OPTIONS = ("ccr", "processors", "heterogeneity", "seed")


#: The maxima of README "Limits" (continuum/engine/core/limits.py), the same as the API's.
LIMITS = limits.get()

def json_object(text: str | None, not_object: str) -> dict:
    """A form's optional JSON-object text field: {} when empty, a message naming line and column when broken."""
    text = (text or "").strip()
    if not text:
        return {}
    try:
        value = loads_json(text)
    except InputError as exc:
        message = str(exc)
        raise forms.ValidationError(f"not JSON ({message})" if message.startswith("malformed") else message) from exc
    if not isinstance(value, dict):
        raise forms.ValidationError(not_object)
    return value


class FleetChoiceMixin:
    """A fleet field asked for only when the user has several fleets."""

    def setup_fleet(self, fleets) -> None:
        self.fields["fleet"].queryset = fleets
        self.fleets = fleets
        self.single_fleet = fleets.count() == 1
        if self.single_fleet:
            # The only possible fleet: no question to ask.
            self.fields["fleet"].initial = fleets.first()
            self.fields["fleet"].required = False
            self.fields["fleet"].widget = forms.HiddenInput()

    def clean_fleet_choice(self, data: dict) -> None:
        if not self.fleets.exists():
            raise forms.ValidationError("you are not a member of any fleet, so there is nowhere to store it")
        if self.single_fleet and not data.get("fleet") and "fleet" not in self.errors:
            data["fleet"] = self.fleets.first()


def _store(fleet, graph, source_format: str, user) -> Application:
    app = Application(fleet=fleet, name=graph.name, source_format=source_format, created_by=user)
    app.set_graph(graph)
    app.save()
    return app


class UploadForm(FleetChoiceMixin, forms.Form):
    """A DAG file in any supported format; the fleet is asked for only when the user has several."""

    file = BoundedFormFileField(help_text=FORMAT_HELP)
    format = forms.ChoiceField(
        choices=[("", "from the file name or content"), *((f, f) for f in FORMATS)], required=False, label="Format"
    )
    name = forms.CharField(max_length=200, required=False, help_text="default: the name in the file")
    ccr = forms.FloatField(min_value=0, required=False, label="CCR", help_text="communication-to-computation ratio")
    processors = forms.IntegerField(
        min_value=1,
        max_value=LIMITS.processors,
        required=False,
        help_text="cost per processor p0.. (unrelated machines)",
    )
    heterogeneity = forms.FloatField(min_value=0, max_value=2, required=False, help_text="beta, 0 to 2")
    seed = forms.IntegerField(min_value=0, required=False, help_text="for the drawn data and costs")
    fleet = forms.ModelChoiceField(queryset=None, required=True, empty_label=None)

    def __init__(self, *args, fleets, **kwargs):
        super().__init__(*args, **kwargs)
        self.setup_fleet(fleets)

    def clean(self):
        data = super().clean()
        self.clean_fleet_choice(data)
        upload = data.get("file")
        if upload is None:
            return data
        options = {k: data[k] for k in STG_OPTIONS if data.get(k) is not None}
        try:
            data["graph"], data["source_format"] = read_dag_file(
                upload.read(), upload.name, data.get("format") or None, options, data.get("name") or None
            )
            data["warnings"] = data["graph"].meta.pop("warnings", [])  # shown once, not stored
        except InputError as exc:
            if exc.field == "options":
                self.add_error(None, f"STG options: {exc}")
            else:
                self.add_error("file", str(exc))
        return data

    def save(self, user) -> Application:
        return _store(self.cleaned_data["fleet"], self.cleaned_data["graph"], self.cleaned_data["source_format"], user)


class GenerateForm(FleetChoiceMixin, forms.Form):
    """A seeded synthetic DAG: the thesis' Tree/Linear CPU/GPU DAGs or the HEFT literature's layered graphs."""

    GENERATORS = [
        ("thesis", "thesis: OpenVX-like CPU/GPU DAG (Tree or Linear)"),
        ("layered", "layered: random DAG of the HEFT literature"),
    ]
    generator = forms.ChoiceField(choices=GENERATORS, initial="thesis", widget=forms.RadioSelect)
    n = forms.IntegerField(
        min_value=2, max_value=LIMITS.tasks, required=False, label="Tasks", help_text="default: drawn"
    )
    seed = forms.IntegerField(min_value=0, initial=0)
    dag_class = forms.ChoiceField(
        choices=[("", "drawn from the seed"), *((s, s) for s in SHAPES)], required=False, label="Class (thesis)"
    )
    ccr = forms.FloatField(min_value=0, required=False, label="CCR (layered)")
    processors = forms.IntegerField(
        min_value=1,
        max_value=LIMITS.processors,
        required=False,
        label="Processors (layered)",
        help_text="unrelated costs p0..",
    )
    heterogeneity = forms.FloatField(min_value=0, max_value=2, required=False, label="Heterogeneity (layered)")
    fleet = forms.ModelChoiceField(queryset=None, required=True, empty_label=None)

    def __init__(self, *args, fleets, **kwargs):
        super().__init__(*args, **kwargs)
        self.setup_fleet(fleets)

    def clean(self):
        data = super().clean()
        self.clean_fleet_choice(data)
        generator = data.get("generator")
        if not generator:
            return data
        params = {"seed": data.get("seed"), "n": data.get("n")}
        if generator == "thesis":
            params["dag_class"] = data.get("dag_class") or None
            for field in ("ccr", "processors", "heterogeneity"):
                if data.get(field) is not None:
                    self.add_error(field, "the layered generator's; leave it empty for a thesis DAG")
        else:
            if data.get("dag_class"):
                self.add_error("dag_class", "the thesis generator's; leave it empty for a layered DAG")
            params.update({k: data.get(k) for k in ("ccr", "processors", "heterogeneity")})
        if self.errors:
            return data
        try:
            data["graph"] = generate_dag(generator, **params)
        except InputError as exc:
            self.add_error(exc.field if exc.field in self.fields else None, str(exc))
        return data

    def save(self, user) -> Application:
        data = self.cleaned_data
        return _store(data["fleet"], data["graph"], f"generator:{data['generator']}", user)


class TargetForm(forms.Form):
    """Where to schedule (one of the fleet's clusters, or N CPUs + M GPUs) and for how many frames."""

    TARGETS = [("cluster", "a cluster (its Ready nodes)"), ("platform", "a model platform")]

    target = forms.ChoiceField(choices=TARGETS, widget=forms.RadioSelect, initial="platform")
    cluster = forms.ModelChoiceField(queryset=None, required=False, empty_label="— choose a cluster —")
    cpus = forms.IntegerField(min_value=0, max_value=LIMITS.processors, initial=4, required=False, label="CPUs")
    gpus = forms.IntegerField(min_value=0, max_value=LIMITS.processors, initial=0, required=False, label="GPUs")
    shared_memory = forms.BooleanField(
        required=False,
        label="one board (shared memory)",
        help_text="only CPU-GPU transfers cost, as on the thesis' CPU+iGPU boards",
    )
    frames = forms.IntegerField(min_value=1, max_value=LIMITS.frames, required=False, help_text="pipelined frames")
    fps = forms.FloatField(min_value=1e-9, required=False, label="FPS", help_text="camera rate (frame f at f/fps)")
    period = forms.FloatField(min_value=0, required=False, help_text="or a frame period, in the DAG's time unit")
    batch = forms.IntegerField(
        min_value=1, max_value=LIMITS.frames, required=False, help_text="frames released together"
    )

    FRAME_FIELDS = ("frames", "fps", "period", "batch")

    def __init__(self, *args, application: Application, **kwargs):
        super().__init__(*args, **kwargs)
        self.application = application
        self.fields["cluster"].queryset = Cluster.objects.filter(fleet_id=application.fleet_id)
        if self.fields["cluster"].queryset.exists():
            self.fields["target"].initial = "cluster"

    def clean(self):
        data = super().clean()
        if data.get("fps") is not None and data.get("period") is not None:
            self.add_error("fps", "give either FPS or a period, not both")
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
            cpus, gpus = data.get("cpus") or 0, data.get("gpus") or 0
            try:
                platform = board(cpus, gpus) if data.get("shared_memory") else Platform.homogeneous(cpus, gpus)
            except InputError as exc:
                self.add_error("cpus", "need at least one processor" if cpus + gpus == 0 else str(exc))
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

    def frame_options(self) -> dict:
        return {k: self.cleaned_data[k] for k in self.FRAME_FIELDS if self.cleaned_data.get(k) is not None}

    def target_arguments(self) -> dict:
        data = self.cleaned_data
        if data["target"] == "cluster":
            return {"cluster": data["cluster"].pk}
        return {"platform": data["platform"]}


class ScheduleForm(TargetForm):
    """Schedule an application with one algorithm, for one frame or several."""

    algorithm = forms.ChoiceField(choices=[], initial="heft")
    params = forms.CharField(
        required=False,
        widget=forms.Textarea(attrs={"rows": 2, "placeholder": '{"rank_mode": "mean"}'}),
        help_text="algorithm parameters as a JSON object (optional)",
    )

    field_order = ["algorithm"]

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.fields["algorithm"].choices = [(name, name.upper()) for name in sorted(algorithms.SCHEDULERS)]

    def clean_params(self) -> dict:
        return json_object(self.cleaned_data.get("params"), "parameters must be a JSON object")

    def clean(self):
        data = super().clean()
        clash = sorted(k for k in self.FRAME_FIELDS if data.get(k) is not None and k in (data.get("params") or {}))
        if clash:
            self.add_error("params", f"{clash[0]} is given both as a field and in the parameters")
        return data

    def job_arguments(self) -> dict:
        data = self.cleaned_data
        params = {**data["params"], **self.frame_options()}
        return {"application": self.application.pk, "algorithm": data["algorithm"], "params": params} | (
            self.target_arguments()
        )


class CompareForm(TargetForm):
    """Run several algorithms on an application and compare them."""

    algorithms = forms.MultipleChoiceField(
        choices=[], widget=forms.CheckboxSelectMultiple, initial=list(DEFAULT_ALGORITHMS)
    )
    rank_mode = forms.ChoiceField(
        choices=[(m, m) for m in RANK_MODES],
        initial="max",
        label="Rank cost",
        help_text="max: the thesis (Fig. 3.1); mean: the literature",
    )

    field_order = ["algorithms"]

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.fields["algorithms"].choices = [(name, name.upper()) for name in algorithms.SCHEDULERS]

    def job_arguments(self) -> dict:
        data = self.cleaned_data
        chosen = [name for name in algorithms.SCHEDULERS if name in data["algorithms"]]
        arguments = {"application": self.application.pk, "algorithms": chosen, "rank_mode": data["rank_mode"]}
        return arguments | self.frame_options() | self.target_arguments()


class AdviceForm(forms.Form):
    """An application's profile on a UMA board (the API's advise request, as a form)."""

    MODELS = [("SC", "standard copy (SC)"), ("UM", "unified memory (UM)"), ("ZC", "zero copy (ZC)")]

    cpu_usage = forms.FloatField(min_value=0, required=False, label="CPU usage %")
    miss_rate_l1 = forms.FloatField(min_value=0, max_value=1, required=False, label="CPU L1 miss rate")
    miss_rate_ll = forms.FloatField(min_value=0, max_value=1, required=False, label="CPU LLC miss rate")
    gpu_usage = forms.FloatField(min_value=0, required=False, label="GPU usage %")
    transactions = forms.FloatField(min_value=0, required=False, label="GPU memory transactions")
    transaction_bytes = forms.FloatField(min_value=0, required=False, label="bytes per transaction")
    hit_rate_l1 = forms.FloatField(min_value=0, max_value=1, required=False, label="GPU L1 hit rate")
    kernel_runtime_s = forms.FloatField(min_value=1e-12, required=False, label="kernel runtime (s)")
    current_model = forms.ChoiceField(choices=MODELS, initial="SC", label="CUDA model now")
    kernel_time = forms.FloatField(
        min_value=1e-12, required=False, label="kernel time", help_text="SC runtime (ZC runtime if on ZC)"
    )
    copy_time = forms.FloatField(min_value=0, required=False, label="copy time per kernel")
    cpu_time = forms.FloatField(min_value=0, required=False, label="CPU work time")
    gpu_time = forms.FloatField(min_value=0, required=False, label="GPU work time")
    cpu_workers = forms.IntegerField(min_value=0, max_value=64, initial=1, label="CPU nodes (N)")
    gpu_workers = forms.IntegerField(min_value=0, max_value=64, initial=1, label="GPU nodes (M)")
    off_board = forms.BooleanField(required=False, label="a node runs off this board")
    single_process = forms.BooleanField(required=False, label="all nodes in one process")

    def request_data(self) -> dict:
        return {k: v for k, v in self.cleaned_data.items() if v is not None}
