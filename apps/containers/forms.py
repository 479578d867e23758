"""The ROS pages' forms. Clustering and placement requests are presentation layers over the API's request
contracts (:class:`~.serializers.ClusterRequestSerializer`, :class:`~.serializers.PlaceRequestSerializer`,
through :class:`apps.ui.forms.SerializerForm`), so a form and the API refuse the same input with the same
message and start the same job."""

from __future__ import annotations

from django import forms

from apps.clusters.models import Cluster
from apps.ui.forms import FleetSerializerForm, SerializerForm, contract_field, json_object, preselect_only
from continuum.engine.containers.rosgraph import LEVELS, MODES, READERS, RosGraph

from . import services
from .charts import LEVEL_LABELS
from .models import Clustering
from .models import RosGraph as RosGraphRow
from .serializers import ClusterRequestSerializer, PlaceRequestSerializer, RosGraphImportSerializer

FORMAT_LABELS = dict(RosGraphRow.Format.choices)
PLATFORMS = [("amd64", "amd64"), ("arm64", "arm64"), ("riscv64", "riscv64")]


class RosGraphUploadForm(FleetSerializerForm):
    """A ROS graph file: the API's import request (:class:`~.serializers.RosGraphImportSerializer`) as a form."""

    serializer_class = RosGraphImportSerializer

    file = forms.FileField(help_text="continuum.rosgraph/v1, Autoware reference system JSON, iRobot topology, .dot")
    format = contract_field(
        RosGraphImportSerializer,
        "format",
        choices=[("", "guess from the file"), *((f, FORMAT_LABELS.get(f, f)) for f in READERS)],
        help_text="",
    )
    name = contract_field(RosGraphImportSerializer, "name")
    fleet = forms.ModelChoiceField(queryset=None, required=True, empty_label=None)

    def serializer_data(self, data: dict) -> dict:
        return {k: data[k] for k in ("file", "format", "name") if data.get(k) not in (None, "")}


class LevelsForm(forms.Form):
    """One choice per ROS node: a Fig. 3.19 level, or the level proposed from the graph's structure."""

    def __init__(self, *args, graph: RosGraph, **kwargs):
        super().__init__(*args, **kwargs)
        self.graph = graph
        proposed = graph.levels()
        for name, node in sorted(graph.nodes.items()):
            field = forms.ChoiceField(
                label=name,
                required=False,
                initial=node.level or "",
                choices=[("", f"proposed: {LEVEL_LABELS[proposed[name]]}"), *((lv, LEVEL_LABELS[lv]) for lv in LEVELS)],
            )
            field.ros_node = name
            self.fields[f"level:{name}"] = field

    def levels(self) -> dict[str, str | None]:
        return {f.ros_node: self.cleaned_data.get(key) or None for key, f in self.fields.items()}


class ClusterForm(SerializerForm):
    serializer_class = ClusterRequestSerializer
    C = ClusterRequestSerializer

    containers = contract_field(C, "containers", label="Containers (N)", help_text="")
    memory_mib = contract_field(C, "memory_mib", label="Memory for containers (MiB)", help_text="")
    overhead_mib = contract_field(
        C, "overhead_mib", label="Overhead per container (MiB)", help_text="29 Docker, 39 K3s (Table 4.17)"
    )
    mode = contract_field(
        C, "mode", choices=[(m, m.replace("_", " ")) for m in MODES], required=True, label="Eq. 3.12", help_text=""
    )
    max_cluster_share = contract_field(C, "max_cluster_share", label="Largest share of ROS nodes")
    max_cluster_memory_mib = contract_field(C, "max_cluster_memory_mib", label="Largest container memory (MiB)")
    distro_image = forms.CharField(initial=services.IMAGE_DEFAULTS["distro_image"], label="ROS base image")
    ros_distro = forms.CharField(initial=services.IMAGE_DEFAULTS["ros_distro"], label="ROS distribution")
    distro_mib = forms.FloatField(min_value=0, initial=0, label="Base image size (MiB)")
    platforms = forms.MultipleChoiceField(
        choices=PLATFORMS, initial=services.IMAGE_DEFAULTS["platforms"], widget=forms.CheckboxSelectMultiple
    )
    repository = forms.CharField(initial=services.IMAGE_DEFAULTS["repository"], required=False)
    tag = forms.CharField(initial=services.IMAGE_DEFAULTS["tag"])

    IMAGE_FIELDS = ("distro_image", "ros_distro", "distro_mib", "platforms", "repository", "tag")

    def serializer_data(self, data: dict) -> dict:
        payload = {k: v for k, v in data.items() if k not in self.IMAGE_FIELDS and v not in (None, "")}
        payload["images"] = {k: data[k] for k in self.IMAGE_FIELDS if data.get(k) not in (None, "")}
        return payload

    def job_arguments(self, rosgraph: RosGraphRow) -> dict:  # type: ignore[override]
        return self.serializer.job_arguments(rosgraph)


class PlaceForm(SerializerForm):
    POLICIES = [
        ("superclustering", "super-clustering (bandwidth, Eqs. 3.14-3.15)"),
        ("default-kubernetes", "default Kubernetes (least allocated + balanced)"),
    ]

    cluster = forms.ModelChoiceField(queryset=None, empty_label="— choose a cluster —")
    policy = forms.ChoiceField(choices=POLICIES, initial="superclustering", widget=forms.RadioSelect)
    overhead_mib = forms.FloatField(min_value=0, initial=0, label="Runtime memory per container (MiB)")
    seed = forms.IntegerField(initial=0, help_text="tie-break seed of the default-Kubernetes policy")
    compare = forms.BooleanField(required=False, initial=True, label="Also run the other policy for comparison")
    overrides = forms.CharField(
        required=False,
        widget=forms.Textarea(attrs={"rows": 3, "placeholder": '{"BehaviorPlanner": {"cpu": 1.5, "priority": 1}}'}),
        help_text="per container: cpu, memory_mib, priority, archs, node, node_selector, tolerations (JSON)",
    )

    def __init__(self, *args, clustering: Clustering, request, **kwargs):
        super().__init__(*args, **kwargs)
        self.clustering = clustering
        self.request = request
        self.fields["cluster"].queryset = Cluster.objects.filter(fleet_id=clustering.fleet_id).order_by("name")
        preselect_only(self.fields["cluster"])

    def clean_overrides(self) -> dict:
        return json_object(self.cleaned_data.get("overrides"), "a JSON object: container name -> changes")

    serializer_class = PlaceRequestSerializer
    error_fields = {"containers": "overrides", "clustering": "cluster"}

    def serializer_context(self) -> dict:
        return {"request": self.request}

    def serializer_data(self, data: dict) -> dict:
        return {
            "cluster": data["cluster"].pk,
            "policy": data["policy"],
            "clustering": self.clustering.pk,
            "overrides": data.get("overrides") or {},
            "overhead_mib": data["overhead_mib"],
            "seed": data["seed"],
            "compare": data.get("compare", False),
        }
